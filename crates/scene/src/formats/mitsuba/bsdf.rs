//! `<bsdf>` elements: `diffuse`, `conductor`, `roughconductor`, `dielectric` and a
//! `twosided` around one of them, into a [`Material`] that carries the physical
//! [`Bsdf`] for the path tracer and Phong coefficients approximating it for Whitted.
//!
//! Defaults are Mitsuba 3's: `diffuse` reflectance 0.5; conductors `material="none"` (a
//! perfect mirror: eta 0, k 1) unless a preset or `eta`/`k` is given; `roughconductor`
//! Beckmann with alpha 0.1; `dielectric` `int_ior` BK7 (1.5046) and `ext_ior` air
//! (1.000277), by number or by Mitsuba's names.

use super::props::Props;
use super::tree::Elem;
use crate::{Bsdf, BsdfKind, Color, LoadError, Material, Microfacet, Roughness};
use glam::DVec3;

/// Mitsuba 3's conductor presets, as its `scalar_rgb` variant turns their measured
/// spectral indices into RGB (read back from Mitsuba 3.9.1): name, eta, k.
const CONDUCTORS: &[(&str, [f32; 3], [f32; 3])] = &[
    ("Ag", [0.155276, 0.116728, 0.138388], [4.828354, 3.122222, 2.146901]),
    ("Al", [1.657501, 0.880405, 0.521244], [9.223811, 6.269502, 4.837004]),
    ("Au", [0.143036, 0.375307, 1.442045], [3.982997, 2.385556, 1.603359]),
    ("Be", [4.185012, 3.185029, 2.784061], [3.835466, 3.010122, 2.868994]),
    ("Cr", [4.369668, 2.916505, 1.654905], [5.206547, 4.231306, 3.754699]),
    ("Cu", [0.201005, 0.92375, 1.102215], [3.913262, 2.453045, 2.14209]),
    ("Hg", [2.398939, 1.440028, 0.90957], [6.327587, 4.371925, 3.421764]),
    ("Ir", [3.0863, 2.082191, 1.617915], [5.592153, 4.067088, 3.267312]),
    ("K", [0.064043, 0.04641, 0.038185], [2.1042, 1.34894, 0.913126]),
    ("Li", [0.265791, 0.195618, 0.220949], [3.540155, 2.311123, 1.668607]),
    ("Mo", [4.483974, 3.525131, 2.77631], [4.111437, 3.420827, 3.150607]),
    ("Na_palik", [0.060269, 0.056141, 0.061988], [3.179273, 2.11249, 1.579041]),
    ("Nb", [3.420074, 2.790093, 2.395629], [3.441395, 2.737666, 2.579746]),
    ("Ni_palik", [2.367305, 1.663373, 1.467078], [4.498812, 3.050153, 2.345439]),
    ("Rh", [2.585793, 1.860216, 1.554263], [6.78226, 4.702987, 3.976073]),
    ("Ta", [2.062721, 2.392939, 2.627929], [2.40836, 1.741486, 1.947028]),
    ("TiN", [1.64845, 1.150516, 1.379823], [3.368328, 1.943498, 1.102068]),
    ("V_palik", [4.277582, 3.512949, 2.761071], [3.491301, 2.889455, 3.111522]),
    ("W", [4.370817, 3.300246, 2.998407], [3.500641, 2.604874, 2.273233]),
];

/// Mitsuba's named indices of refraction (its `ior` list).
const IORS: &[(&str, f32)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.333),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.47),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.575),
    ("diamond", 2.419),
];

fn rgb(c: DVec3) -> Color {
    c.as_vec3()
}

/// The material of a `<bsdf>` element.
pub(super) fn read_bsdf(e: &Elem) -> Result<Material, LoadError> {
    let ty = e.required("type")?;
    let mut p = Props::new(e)?;
    let name = e.attr("id").unwrap_or("").to_string();
    let material = match ty {
        "twosided" => {
            let inner = p.objects("bsdf");
            let [one] = inner.as_slice() else {
                return Err(e.error(format!(
                    "<bsdf type=\"twosided\"> takes exactly one nested <bsdf> (dynray has no different back side), not {}",
                    inner.len()
                )));
            };
            let mut m = read_bsdf(one)?;
            match &mut m.bsdf {
                Some(b) if matches!(b.kind, BsdfKind::Dielectric { .. }) => {
                    return Err(one.error("a dielectric already has two sides: `twosided` around it is not supported"))
                }
                Some(b) => b.two_sided = true,
                None => unreachable!("read_bsdf always sets a BSDF"),
            }
            Material { name, ..m }
        }
        "diffuse" => {
            let reflectance = rgb(p.color("reflectance", false)?.unwrap_or(DVec3::splat(0.5)));
            let mut m = phong_base(name);
            m.diffuse = reflectance;
            m.bsdf = Some(Bsdf::diffuse(reflectance));
            m
        }
        "conductor" | "roughconductor" => {
            let (eta, k) = conductor_ior(&mut p)?;
            let specular_reflectance = rgb(p.color("specular_reflectance", false)?.unwrap_or(DVec3::ONE));
            let roughness = if ty == "roughconductor" { Some(roughness(&mut p)?) } else { None };
            let mut m = phong_base(name);
            // Whitted sees a mirror of the conductor's normal-incidence reflectance.
            m.specular = specular_reflectance * normal_reflectance(eta, k);
            m.bsdf = Some(Bsdf { kind: BsdfKind::Conductor { eta, k, specular_reflectance, roughness }, two_sided: false });
            m
        }
        "dielectric" => {
            let int_ior = ior(&mut p, "int_ior", 1.5046)?;
            let ext_ior = ior(&mut p, "ext_ior", 1.000277)?;
            let specular_reflectance = rgb(p.color("specular_reflectance", false)?.unwrap_or(DVec3::ONE));
            let specular_transmittance = rgb(p.color("specular_transmittance", false)?.unwrap_or(DVec3::ONE));
            let mut m = phong_base(name);
            m.transparency = specular_transmittance;
            m.ior = int_ior / ext_ior;
            m.bsdf = Some(Bsdf {
                kind: BsdfKind::Dielectric { int_ior, ext_ior, specular_reflectance, specular_transmittance },
                two_sided: false,
            });
            m
        }
        other => {
            return Err(e.error(format!(
                "<bsdf type=\"{other}\"> is not supported (dynray reads diffuse, conductor, roughconductor, dielectric, twosided)"
            )))
        }
    };
    p.finish()?;
    Ok(material)
}

/// A material with no Phong terms at all (Mitsuba scenes have no ambient light).
fn phong_base(name: String) -> Material {
    Material {
        name,
        ambient: Color::ZERO,
        diffuse: Color::ZERO,
        spot: Color::ZERO,
        shine: 1.0,
        specular: Color::ZERO,
        transparency: Color::ZERO,
        ior: 1.0,
        diffuse_texture: None,
        emission: Color::ZERO,
        bsdf: None,
    }
}

/// A conductor's `eta` and `k`: from `material` (a preset or `none`), or given.
fn conductor_ior(p: &mut Props<'_>) -> Result<(Color, Color), LoadError> {
    let preset = p.string("material")?;
    let (eta, k) = (p.color("eta", true)?, p.color("k", true)?);
    match (preset, eta, k) {
        (None, Some(eta), Some(k)) => Ok((rgb(eta), rgb(k))),
        (None, None, None) => Ok((Color::ZERO, Color::ONE)),
        (None, _, _) => Err(p.elem.error("a conductor needs both `eta` and `k`, or a `material` preset")),
        (Some((name, at)), None, None) => {
            if name == "none" {
                return Ok((Color::ZERO, Color::ONE));
            }
            CONDUCTORS
                .iter()
                .find(|c| c.0 == name)
                .map(|c| (Color::from_array(c.1), Color::from_array(c.2)))
                .ok_or_else(|| {
                    let known: Vec<&str> = CONDUCTORS.iter().map(|c| c.0).collect();
                    at.error(format!(
                        "conductor material `{name}` is not known (dynray has none, {})",
                        known.join(", ")
                    ))
                })
        }
        (Some((_, at)), _, _) => {
            Err(at.error("give a conductor either a `material` preset or `eta` and `k`, not both"))
        }
    }
}

/// `distribution`, `alpha` or `alpha_u`/`alpha_v` of a rough conductor.
fn roughness(p: &mut Props<'_>) -> Result<Roughness, LoadError> {
    let distribution = match p.string("distribution")? {
        None => Microfacet::Beckmann,
        Some((d, at)) => match d.as_str() {
            "beckmann" => Microfacet::Beckmann,
            "ggx" => Microfacet::Ggx,
            _ => return Err(at.error(format!("microfacet distribution `{d}` (expected beckmann or ggx)"))),
        },
    };
    // Mitsuba samples visible normals by default; dynray always does (same expectation).
    p.boolean("sample_visible", true)?;
    let alpha = p.float("alpha", 0.1)?;
    let (au, av) = (p.float("alpha_u", alpha)?, p.float("alpha_v", alpha)?);
    for a in [au, av] {
        if !(a > 0.0) {
            return Err(p.elem.error(format!("roughness {a}: must be positive (use `conductor` for a mirror)")));
        }
    }
    Ok(Roughness { distribution, alpha_u: au as f32, alpha_v: av as f32 })
}

/// An index of refraction given as a number or one of Mitsuba's names.
fn ior(p: &mut Props<'_>, name: &str, default: f32) -> Result<f32, LoadError> {
    if p.tag_of(name) == Some("string") {
        let (text, at) = p.string(name)?.expect("a <string> is there");
        return IORS.iter().find(|(n, _)| *n == text).map(|(_, v)| *v).ok_or_else(|| {
            at.error(format!("`{name}`: `{text}` is not an index of refraction Mitsuba names (e.g. air, water, bk7)"))
        });
    }
    let v = p.float(name, default as f64)?;
    if !(v > 0.0) {
        return Err(p.elem.error(format!("`{name}` {v}: an index of refraction is positive")));
    }
    Ok(v as f32)
}

/// Fresnel reflectance of a conductor at normal incidence, per channel.
fn normal_reflectance(eta: Color, k: Color) -> Color {
    let num = (eta - Color::ONE) * (eta - Color::ONE) + k * k;
    let den = (eta + Color::ONE) * (eta + Color::ONE) + k * k;
    num / den.max(Color::splat(1e-12))
}
