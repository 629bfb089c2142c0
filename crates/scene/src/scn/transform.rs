//! Transforms (seed 003 A.8): `translate`, `rotate base dir angle`, `rotate_x/y/z`,
//! `scale base factors`, applied to the object in the order written, composed in `f64`.
//!
//! Angles are in degrees and follow the right-hand rule: with the thumb along the axis
//! (`dir`, or +x/+y/+z), positive angles turn counter-clockwise seen from the thumb's tip.

use super::parser::{Def, Parser, R};
use glam::{DMat4, DVec3};

/// `T(base) · R(dir, deg) · T(-base)`: rotation about the line through `base` along `dir`.
pub fn rotate_about(base: DVec3, dir: DVec3, deg: f64) -> DMat4 {
    DMat4::from_translation(base)
        * DMat4::from_axis_angle(dir.normalize(), deg.to_radians())
        * DMat4::from_translation(-base)
}

/// `T(base) · S(factors) · T(-base)`: scaling that keeps `base` fixed.
pub fn scale_about(base: DVec3, factors: DVec3) -> DMat4 {
    DMat4::from_translation(base) * DMat4::from_scale(factors) * DMat4::from_translation(-base)
}

impl Parser<'_> {
    /// `transform { op* }` or `transform name`; the keyword is already consumed. The
    /// result maps object points to world points: the first operation written is the first
    /// applied.
    pub(crate) fn transform(&mut self) -> R<DMat4> {
        if let Some(named) = self.named("a transform", |d| match d {
            Def::Transform(m) => Some(*m),
            _ => None,
        })? {
            return Ok(named);
        }
        let mut m = DMat4::IDENTITY;
        let ops = ["translate", "rotate", "rotate_x", "rotate_y", "rotate_z", "scale"];
        self.block("transform", &ops, &ops, |p, key, span| {
            let step = match key {
                "translate" => DMat4::from_translation(p.vector64("translation")?),
                "rotate" => {
                    let base = p.vector64("rotation base point")?;
                    let start = p.span().start;
                    let dir = p.vector64("rotation axis direction")?;
                    if dir == DVec3::ZERO {
                        return Err(p
                            .err(start..p.prev_end(), "rotation axis is the zero vector")
                            .label("expected a non-zero axis direction"));
                    }
                    let deg = p.real("rotation angle (degrees)")?;
                    rotate_about(base, dir, deg)
                }
                "rotate_x" => DMat4::from_rotation_x(p.real("rotate_x angle (degrees)")?.to_radians()),
                "rotate_y" => DMat4::from_rotation_y(p.real("rotate_y angle (degrees)")?.to_radians()),
                "rotate_z" => DMat4::from_rotation_z(p.real("rotate_z angle (degrees)")?.to_radians()),
                "scale" => {
                    let base = p.vector64("scale base point")?;
                    let start = p.span().start;
                    let f = p.vector64("scale factors")?;
                    if f.x == 0.0 || f.y == 0.0 || f.z == 0.0 {
                        return Err(p
                            .err(start..p.prev_end(), format!("scale factors {f} contain a zero"))
                            .label("expected non-zero factors (a zero flattens the object)"));
                    }
                    scale_about(base, f)
                }
                other => return Err(p.unhandled(span, other, "transform")),
            };
            m = step * m;
            Ok(())
        })?;
        Ok(m)
    }
}
