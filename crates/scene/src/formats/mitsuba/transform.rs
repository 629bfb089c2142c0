//! `<transform>`: `translate`, `rotate`, `scale`, `matrix` and `lookat`, applied in the
//! order written (each one to the result of those before it, Mitsuba's rule), in `f64`.

use super::props::{numbers, xyz};
use super::tree::Elem;
use crate::LoadError;
use glam::{DMat4, DVec3, DVec4};

/// The matrix of a `<transform>` element.
pub(super) fn parse_transform(e: &Elem) -> Result<DMat4, LoadError> {
    e.only_attrs(&["name"])?;
    let mut m = DMat4::IDENTITY;
    for op in &e.children {
        let step = match op.tag.as_str() {
            "translate" => DMat4::from_translation(xyz(op, 0.0)?),
            "scale" => DMat4::from_scale(xyz(op, 1.0)?),
            "rotate" => {
                op.only_attrs(&["x", "y", "z", "value", "angle"])?;
                let angle = op.required("angle")?;
                let angle = super::props::number(op, angle)?;
                let axis = xyz(&without(op, "angle"), 0.0)?;
                if !(axis.length_squared() > 0.0) {
                    return Err(op.error("<rotate>: the axis is zero"));
                }
                DMat4::from_axis_angle(axis.normalize(), angle.to_radians())
            }
            "matrix" => {
                op.only_attrs(&["value"])?;
                let v = numbers(op, op.required("value")?)?;
                match v.len() {
                    16 => DMat4::from_cols_array(&v.try_into().expect("16 numbers")).transpose(),
                    9 => {
                        let r = DMat4::from_cols_array(&[
                            v[0], v[1], v[2], 0.0, v[3], v[4], v[5], 0.0, v[6], v[7], v[8], 0.0, 0.0, 0.0, 0.0, 1.0,
                        ]);
                        r.transpose()
                    }
                    n => return Err(op.error(format!("<matrix>: `value` has 16 (or 9) numbers, not {n}"))),
                }
            }
            "lookat" => lookat(op)?,
            other => return Err(op.error(format!("<transform>: <{other}> is not a transform operation"))),
        };
        m = step * m;
    }
    if !m.is_finite() {
        return Err(e.error("<transform>: the matrix is not finite"));
    }
    Ok(m)
}

/// `op` without the attribute `name` (so `xyz` can read a rotation's axis).
fn without(op: &Elem, name: &str) -> Elem {
    Elem { attrs: op.attrs.iter().filter(|(k, _)| k != name).cloned().collect(), ..op.clone() }
}

/// Mitsuba's look-at matrix: columns `[left, up', dir, origin]`, `dir` from `origin`
/// to `target`, `left = normalize(up × dir)`, `up' = dir × left` (camera space has +x to
/// the image's left).
fn lookat(op: &Elem) -> Result<DMat4, LoadError> {
    op.only_attrs(&["origin", "target", "up"])?;
    let vec = |k: &str| -> Result<DVec3, LoadError> {
        let v = numbers(op, op.required(k)?)?;
        match v.as_slice() {
            [x, y, z] => Ok(DVec3::new(*x, *y, *z)),
            _ => Err(op.error(format!("<lookat>: `{k}` has 3 numbers, not {}", v.len()))),
        }
    };
    let (origin, target) = (vec("origin")?, vec("target")?);
    let up = if op.attr("up").is_some() { vec("up")? } else { DVec3::Y };
    let dir = (target - origin).normalize_or_zero();
    let left = up.cross(dir).normalize_or_zero();
    if dir == DVec3::ZERO || left == DVec3::ZERO {
        return Err(op.error("<lookat>: origin equals target, or up is parallel to the view direction"));
    }
    let new_up = dir.cross(left);
    Ok(DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        DVec4::new(origin.x, origin.y, origin.z, 1.0),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;
    use std::sync::Arc;

    fn el(tag: &str, attrs: &[(&str, &str)], children: Vec<Elem>) -> Elem {
        Elem {
            tag: tag.into(),
            attrs: attrs.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect(),
            children,
            file: Arc::new(PathBuf::from("t.xml")),
            root: Arc::new(PathBuf::from("t.xml")),
            line: 1,
        }
    }

    /// The reference scene's plane: scale 1000, rotate −90° about x, translate y −1 puts
    /// the unit rectangle's +z normal on +y at y = −1.
    #[test]
    fn operations_apply_in_written_order() {
        let t = el(
            "transform",
            &[("name", "to_world")],
            vec![
                el("scale", &[("value", "1000")], vec![]),
                el("rotate", &[("x", "1"), ("angle", "-90")], vec![]),
                el("translate", &[("y", "-1")], vec![]),
            ],
        );
        let m = parse_transform(&t).unwrap();
        let n = m.transform_vector3(DVec3::Z).normalize();
        assert!((n - DVec3::Y).length() < 1e-12, "{n}");
        let p = m.transform_point3(DVec3::new(1.0, 1.0, 0.0));
        assert!((p - DVec3::new(1000.0, -1.0, -1000.0)).length() < 1e-9, "{p}");
    }

    /// The to_world matrix the reference README prints for its camera.
    #[test]
    fn lookat_matches_mitsuba() {
        let t = el(
            "transform",
            &[],
            vec![el("lookat", &[("origin", "0, 1, 6"), ("target", "0, 0, 0"), ("up", "0, 1, 0")], vec![])],
        );
        let m = parse_transform(&t).unwrap();
        let want = [[-1.0, 0.0, 0.0, 0.0], [0.0, 0.986394, -0.164399, 1.0], [0.0, -0.164399, -0.986394, 6.0]];
        for (r, row) in want.iter().enumerate() {
            for (c, w) in row.iter().enumerate() {
                assert!((m.row(r)[c] - w).abs() < 1e-6, "({r}, {c}): {} vs {w}", m.row(r)[c]);
            }
        }
    }

    #[test]
    fn matrix_is_row_major_and_bad_operations_are_errors() {
        let t = el("transform", &[], vec![el("matrix", &[("value", "1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1")], vec![])]);
        assert_eq!(parse_transform(&t).unwrap().w_axis, DVec4::new(5.0, 6.0, 7.0, 1.0));
        let bad = el("transform", &[], vec![el("shear", &[], vec![])]);
        assert!(parse_transform(&bad).unwrap_err().to_string().contains("t.xml:1: <transform>: <shear>"));
        let short = el("transform", &[], vec![el("matrix", &[("value", "1 2 3")], vec![])]);
        assert!(parse_transform(&short).unwrap_err().to_string().contains("not 3"));
        let zero = el("transform", &[], vec![el("rotate", &[("angle", "10")], vec![])]);
        assert!(parse_transform(&zero).unwrap_err().to_string().contains("axis is zero"));
    }
}
