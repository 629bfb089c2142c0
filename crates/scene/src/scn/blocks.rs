//! The non-geometric blocks (seed 003 A.3–A.7): `light`, `camera`, `environment`,
//! `settings`, `material` with its `finish`. Each reads its parameters through
//! `Parser::block`, so unknown and duplicated parameters are errors everywhere.

use super::animate::{AnimSpec, MAX_FRAMES};
use super::parser::{Def, Parser, R};
use crate::{Camera, Color, Environment, Finish, Light, LightKind, Material, Projection, Settings, TextureRef};
use glam::Vec3;
use std::rc::Rc;

/// Vertical field of view of a perspective camera without `angle`, in degrees.
pub const DEFAULT_ANGLE_DEG: f32 = 45.0;

/// Largest accepted image side, in pixels.
pub const MAX_IMAGE_SIDE: i64 = 16384;

/// Largest accepted `max_recursion_level`.
pub const MAX_RECURSION: i64 = 64;

/// Largest accepted point-light `falloff` exponent.
pub const MAX_FALLOFF: i64 = 8;

impl Parser<'_> {
    /// `light { position V [color C] [falloff I] [animate { … }] }`,
    /// `light { direction V [color C] [animate { … }] }` or `light name`. The keyword
    /// `light` is the current token. An animated light is given in its animation's space.
    pub(crate) fn light(&mut self) -> R<(Light, Option<Rc<AnimSpec>>)> {
        self.bump();
        if let Some(named) = self.named("a light", |d| match d {
            Def::Light(l, a) => Some((*l, a.clone())),
            _ => None,
        })? {
            return Ok(named);
        }
        let (mut pos, mut dir, mut color, mut falloff) = (None, None, None, None);
        let mut falloff_span = None;
        let mut anim = None;
        let keys = ["position", "direction", "color", "falloff", "animate"];
        let block = self.block("light", &keys, &[], |p, key, span| {
            match key {
                "animate" => anim = Some(Rc::new(p.animate(span)?)),
                "position" => pos = Some((p.vector("light position")?, span)),
                "direction" => {
                    let start = p.span().start;
                    let d = p.vector("light direction")?;
                    if d == Vec3::ZERO {
                        return Err(p
                            .err(start..p.prev_end(), "light direction is the zero vector")
                            .label("expected a non-zero direction"));
                    }
                    dir = Some((d, span));
                }
                "color" => color = Some(p.color("light color")?),
                "falloff" => {
                    falloff_span = Some(span);
                    falloff = Some(p.int("falloff exponent", 0, MAX_FALLOFF)? as i32);
                }
                other => return Err(p.unhandled(span, other, "light")),
            }
            Ok(())
        })?;
        let color = color.unwrap_or(Color::ONE);
        let kind = match (pos, dir) {
            (Some((position, _)), None) => LightKind::Point { position, falloff: falloff.unwrap_or(0) },
            (None, Some((direction, _))) => {
                if let Some(s) = falloff_span {
                    return Err(self
                        .err(s, "`falloff` applies only to point lights")
                        .label("a light with `direction` is directional and never attenuates"));
                }
                LightKind::Directional { direction }
            }
            (Some(_), Some((_, s))) => {
                return Err(self
                    .err(s, "a light has either `position` (point) or `direction` (directional), not both")
                    .label("second kind given here"))
            }
            (None, None) => {
                return Err(self
                    .err(block, "missing parameter `position` or `direction` in `light`")
                    .label("expected `position` for a point light or `direction` for a directional one"))
            }
        };
        Ok((Light { kind, color, emitter_stand_in: false }, anim))
    }

    /// `camera { parallel|perspective position V to V up V [angle R] [animate { … }] }` or
    /// `camera name`. An animated camera is given in its animation's space.
    pub(crate) fn camera(&mut self) -> R<(Camera, Option<Rc<AnimSpec>>)> {
        self.bump();
        if let Some(named) = self.named("a camera", |d| match d {
            Def::Camera(c, a) => Some((*c, a.clone())),
            _ => None,
        })? {
            return Ok(named);
        }
        let (mut proj, mut pos, mut to, mut up, mut angle) = (None, None, None, None, None);
        let mut proj_span = None;
        let mut anim = None;
        let block = self.block(
            "camera",
            &["parallel", "perspective", "position", "to", "up", "angle", "animate"],
            &[],
            |p, key, span| {
                match key {
                    "animate" => anim = Some(Rc::new(p.animate(span)?)),
                    "parallel" | "perspective" => {
                        if let Some(first) = proj_span.clone() {
                            return Err(p
                                .err(span, "a camera is either `parallel` or `perspective`, not both")
                                .label("second projection given here")
                                .also(p.file, first, "first given here"));
                        }
                        proj_span = Some(span);
                        proj = Some(key == "parallel");
                    }
                    "position" => pos = Some(p.vector("camera position")?),
                    "to" => to = Some(p.vector("camera focal point `to`")?),
                    "up" => up = Some(p.vector("camera up vector")?),
                    "angle" => angle = Some(p.real_f32("camera angle", "it must be positive", |x| x > 0.0)?),
                    other => return Err(p.unhandled(span, other, "camera")),
                }
                Ok(())
            },
        )?;
        let parallel = self.required(proj, "parallel` or `perspective", "camera", &block)?;
        let position = self.required(pos, "position", "camera", &block)?;
        let look_at = self.required(to, "to", "camera", &block)?;
        let up = self.required(up, "up", "camera", &block)?;
        let view = look_at - position;
        if view.length_squared() == 0.0 || !view.is_finite() {
            return Err(self
                .err(block, "camera `position` and `to` are the same point")
                .label("expected a focal point away from the camera"));
        }
        if view.cross(up).length_squared() <= 1e-12 * view.length_squared() * up.length_squared() {
            return Err(self
                .err(block, "camera `up` is zero or parallel to the view direction")
                .label("expected an up vector not parallel to `to - position`"));
        }
        let projection = if parallel {
            // Without `angle`, a parallel camera shows at the focal point what the default
            // perspective camera would.
            let height = angle.unwrap_or_else(|| 2.0 * view.length() * (DEFAULT_ANGLE_DEG.to_radians() * 0.5).tan());
            Projection::Parallel { height }
        } else {
            let fov_y_deg = angle.unwrap_or(DEFAULT_ANGLE_DEG);
            if fov_y_deg >= 180.0 {
                return Err(self
                    .err(block, format!("perspective camera angle {fov_y_deg} is not below 180 degrees"))
                    .label("expected a field of view between 0 and 180 degrees"));
            }
            Projection::Perspective { fov_y_deg }
        };
        Ok((Camera { position, look_at, up, projection, clip: crate::Clip::NONE }, anim))
    }

    /// `environment { [background C] [ambient C] [ior R] }`; the keyword is consumed.
    pub(crate) fn environment(&mut self) -> R<Environment> {
        let mut env = Environment::default();
        self.block("environment", &["background", "ambient", "ior"], &[], |p, key, span| {
            match key {
                "background" => env.background = p.color("background")?,
                "ambient" => env.ambient = p.color("ambient light")?,
                "ior" => {
                    env.ior = p.real_f32("environment ior", "an index of refraction must be positive", |x| x > 0.0)?
                }
                other => return Err(p.unhandled(span, other, "environment")),
            }
            Ok(())
        })?;
        Ok(env)
    }

    /// `settings { [image_width I] [image_height I] [min_weight R]
    /// [max_recursion_level I] [sphere_detail I] [frames I] [frame_rate R] }`; the keyword
    /// is consumed.
    /// `min_weight` is a real (the seed's grammar says integer, its class says real).
    pub(crate) fn settings(&mut self) -> R<Settings> {
        let mut s = Settings::default();
        let mut detail = None;
        let (mut frames, mut frame_rate) = (None, None);
        self.block(
            "settings",
            &[
                "image_width",
                "image_height",
                "min_weight",
                "max_recursion_level",
                "sphere_detail",
                "frames",
                "frame_rate",
            ],
            &[],
            |p, key, span| {
                match key {
                    "image_width" => s.width = p.int("image_width", 1, MAX_IMAGE_SIDE)? as u32,
                    "image_height" => s.height = p.int("image_height", 1, MAX_IMAGE_SIDE)? as u32,
                    "min_weight" => {
                        s.min_weight =
                            p.real_f32("min_weight", "it must lie in [0, 1]", |x| (0.0..=1.0).contains(&x))?
                    }
                    "max_recursion_level" => {
                        s.max_recursion_level = p.int("max_recursion_level", 1, MAX_RECURSION)? as u32
                    }
                    "sphere_detail" => {
                        detail = Some(p.int(
                            "sphere_detail",
                            super::build::MIN_SPHERE_DETAIL as i64,
                            super::build::MAX_SPHERE_DETAIL as i64,
                        )? as u32)
                    }
                    "frames" => frames = Some(p.int("frames", 1, MAX_FRAMES)? as u32),
                    "frame_rate" => {
                        frame_rate = Some(p.real_f32("frame_rate", "a frame rate must be positive", |x| x > 0.0)?)
                    }
                    other => return Err(p.unhandled(span, other, "settings")),
                }
                Ok(())
            },
        )?;
        if detail.is_some() {
            self.st.sphere_detail = detail;
        }
        self.st.frames = frames;
        self.st.frame_rate = frame_rate;
        Ok(s)
    }

    /// `material { color C [finish { … }] [texture "file"] }` or `material name`; the
    /// keyword is already consumed. `color × finish` follows [`Material::from_finish`].
    pub(crate) fn material(&mut self) -> R<Rc<Material>> {
        if let Some(named) = self.named("a material", |d| match d {
            Def::Material(m) => Some(m.clone()),
            _ => None,
        })? {
            return Ok(named);
        }
        let mut color = None;
        let mut finish = Finish::default();
        let mut texture = None;
        let block = self.block("material", &["color", "finish", "texture"], &[], |p, key, span| {
            match key {
                "color" => color = Some(p.color("material color")?),
                "finish" => finish = p.finish()?,
                "texture" => texture = Some(p.texture_param()?),
                other => return Err(p.unhandled(span, other, "material")),
            }
            Ok(())
        })?;
        let color = self.required(color, "color", "material", &block)?;
        let mut m = Material::from_finish("", color, &finish);
        // The texture multiplies the diffuse and ambient colours (docs §5.1).
        m.diffuse_texture = texture.map(TextureRef::new);
        Ok(Rc::new(m))
    }

    fn finish(&mut self) -> R<Finish> {
        let mut f = Finish::default();
        let keys = ["ambient", "diffuse", "spot", "shine", "specular", "transparency", "ior"];
        self.block("finish", &keys, &[], |p, key, span| {
            let nonneg = |x: f64| x >= 0.0;
            match key {
                "ambient" => f.ambient = p.real_f32("finish ambient", "it must not be negative", nonneg)?,
                "diffuse" => f.diffuse = p.real_f32("finish diffuse", "it must not be negative", nonneg)?,
                "spot" => f.spot = p.real_f32("finish spot", "it must not be negative", nonneg)?,
                "shine" => f.shine = p.real_f32("finish shine", "it must not be negative", nonneg)?,
                "specular" => f.specular = p.real_f32("finish specular", "it must not be negative", nonneg)?,
                "transparency" => {
                    f.transparency = p.real_f32("finish transparency", "it must not be negative", nonneg)?
                }
                "ior" => f.ior = p.real_f32("finish ior", "an index of refraction must be positive", |x| x > 0.0)?,
                other => return Err(p.unhandled(span, other, "finish")),
            }
            Ok(())
        })?;
        Ok(f)
    }

    /// After a keyword: `name` (not `{`) resolves a definition of `kind`.
    pub(crate) fn named<T>(&mut self, kind: &str, pick: impl Fn(&Def) -> Option<T>) -> R<Option<T>> {
        if self.at('{') {
            return Ok(None);
        }
        let (name, span) = self.name(&format!("`{{` or the name of {kind}"))?;
        self.lookup(&name, span, kind, pick).map(Some)
    }
}
