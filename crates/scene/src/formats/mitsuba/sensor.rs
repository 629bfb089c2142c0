//! `<sensor type="perspective">` with its `hdrfilm` and `independent` sampler: the
//! camera, the image size and the samples per pixel.
//!
//! Mitsuba's camera space looks along +z with +y up and **+x to the image's left**; its
//! `to_world` maps that frame into the scene. dynray's camera is an eye, a target and an
//! up vector with the image's right = forward × up, which is Mitsuba's −x exactly when
//! `to_world` is not a mirror, so a mirroring `to_world` is refused. Mitsuba's field of
//! view is along the axis `fov_axis` names; dynray's is vertical, converted here with the
//! film's aspect (so `render --width/--height` with another aspect keeps the vertical
//! angle, not Mitsuba's axis).
//!
//! `near_clip` and `far_clip` (checked: `0 < near < far`) become the camera's
//! [`Clip`]: as in Mitsuba, a camera ray sees only what lies between the planes at those
//! distances along the view axis (Mitsuba moves the ray's origin onto the near plane;
//! dynray keeps the eye as origin and starts the ray's interval there instead).

use super::props::Props;
use super::tree::Elem;
use crate::{Camera, Clip, LoadError, Projection, Warning};
use glam::{DMat4, DVec3};

/// What a sensor says about the image.
pub(super) struct Sensor {
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
    pub spp: u32,
}

/// Largest image edge accepted from a file (the renderer's own limit, 16384).
const MAX_EDGE: i64 = 1 << 14;

pub(super) fn read_sensor(e: &Elem, warnings: &mut Vec<Warning>) -> Result<Sensor, LoadError> {
    let ty = e.required("type")?;
    if ty != "perspective" {
        return Err(e.error(format!("<sensor type=\"{ty}\"> is not supported (dynray reads perspective)")));
    }
    let mut p = Props::new(e)?;
    // Mitsuba's default is a 50 mm lens on 35 mm film; dynray asks for the angle.
    if p.tag_of("fov").is_none() {
        return Err(e.error("the sensor needs a `fov` (dynray does not read `focal_length`)"));
    }
    let fov = p.float("fov", 0.0)?;
    let axis = p.string("fov_axis")?;
    let near = p.float("near_clip", 1e-2)?;
    let far = p.float("far_clip", 1e4)?;
    if !(near > 0.0 && far > near) {
        return Err(e.error(format!("near_clip {near} and far_clip {far}: need 0 < near_clip < far_clip")));
    }
    // A pinhole camera: the focus distance changes nothing.
    p.float("focus_distance", 0.0)?;
    let to_world = p.transform("to_world")?.unwrap_or(DMat4::IDENTITY);
    let (width, height) = match p.objects("film").as_slice() {
        [] => (768, 576),
        [film] => read_film(film, warnings)?,
        [_, second, ..] => return Err(second.error("a sensor has one <film>")),
    };
    let spp = match p.objects("sampler").as_slice() {
        [] => 4,
        [s] => read_sampler(s)?,
        [_, second, ..] => return Err(second.error("a sensor has one <sampler>")),
    };
    p.finish()?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(e.error(format!("`fov` {fov}: need a field of view in (0, 180) degrees")));
    }
    let (w, h) = (width as f64, height as f64);
    let half = (fov.to_radians() * 0.5).tan();
    let axis_name = axis.as_ref().map_or("x", |(a, _)| a.as_str());
    let tan_y = match axis_name {
        "x" => half * h / w,
        "y" => half,
        "smaller" if w <= h => half * h / w,
        "smaller" => half,
        "larger" if w >= h => half * h / w,
        "larger" => half,
        "diagonal" => half * h / (w * w + h * h).sqrt(),
        other => {
            let at = axis.as_ref().map_or(e, |(_, at)| *at);
            return Err(at.error(format!("fov_axis `{other}` (expected x, y, smaller, larger or diagonal)")));
        }
    };
    let fov_y_deg = (2.0 * tan_y.atan()).to_degrees() as f32;
    let origin = to_world.transform_point3(DVec3::ZERO);
    let forward = to_world.transform_vector3(DVec3::Z);
    let up = to_world.transform_vector3(DVec3::Y);
    let left = to_world.transform_vector3(DVec3::X);
    if forward.length_squared() == 0.0 || up.length_squared() == 0.0 {
        return Err(e.error("the sensor's to_world collapses the view direction or the up vector"));
    }
    if up.cross(forward).dot(left) <= 0.0 {
        return Err(e.error("the sensor's to_world mirrors the image (negative determinant): not supported"));
    }
    let forward = forward.normalize();
    let camera = Camera {
        position: origin.as_vec3(),
        look_at: (origin + forward).as_vec3(),
        up: up.normalize().as_vec3(),
        projection: Projection::Perspective { fov_y_deg },
        clip: Clip { near: near as f32, far: far as f32 },
    };
    Ok(Sensor { camera, width, height, spp })
}

fn read_film(e: &Elem, warnings: &mut Vec<Warning>) -> Result<(u32, u32), LoadError> {
    let ty = e.required("type")?;
    if ty != "hdrfilm" {
        return Err(e.error(format!("<film type=\"{ty}\"> is not supported (dynray reads hdrfilm)")));
    }
    let mut p = Props::new(e)?;
    let w = p.integer("width", 768)?;
    let h = p.integer("height", 576)?;
    for (what, v) in [("width", w), ("height", h)] {
        if !(1..=MAX_EDGE).contains(&v) {
            return Err(e.error(format!("film {what} {v} is outside 1..={MAX_EDGE}")));
        }
    }
    // How the file is stored changes nothing about the radiance: dynray writes by the
    // output's extension.
    for name in ["pixel_format", "component_format", "file_format"] {
        p.string(name)?;
    }
    p.boolean("banner", false)?;
    for f in p.objects("rfilter") {
        let ty = f.required("type")?;
        Props::new(f)?.finish()?;
        if ty != "box" {
            warnings.push(Warning::new(
                &f.file,
                Some(f.line),
                format!("reconstruction filter `{ty}`: dynray box-filters (each sample counts for its pixel)"),
            ));
        }
    }
    p.finish()?;
    Ok((w as u32, h as u32))
}

fn read_sampler(e: &Elem) -> Result<u32, LoadError> {
    let ty = e.required("type")?;
    if ty != "independent" {
        return Err(e.error(format!("<sampler type=\"{ty}\"> is not supported (dynray reads independent)")));
    }
    let mut p = Props::new(e)?;
    let n = p.integer("sample_count", 4)?;
    // dynray's own sampler is seeded by `render --seed`; Mitsuba's seed cannot carry over.
    p.integer("seed", 0)?;
    p.finish()?;
    if !(1..=1 << 20).contains(&n) {
        return Err(e.error(format!("sample_count {n} is outside 1..=1048576")));
    }
    Ok(n as u32)
}
