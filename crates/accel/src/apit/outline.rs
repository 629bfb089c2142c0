//! The outline of the A-PIT and the A-buffer: one box, the cube of A-buffers itself,
//! centred on the observer and just large enough to hold the (padded) mesh bounds that
//! rays are clipped to. Nothing is drawn below it: a pixel is an infinite pyramid from the
//! observer and a pixel's tree orders depth intervals along it, neither of which is a box.

use super::build::Base;
use crate::OutlineBox;
use dynray_geom::{Aabb, Vec3};

impl Base {
    /// Pushes the cube at depth 0, as a leaf (whatever `max_depth`: it is all there is).
    pub(super) fn outline(&self, out: &mut Vec<OutlineBox>) {
        let (o, b) = (self.cube.observer_f32, self.cube.bounds);
        if self.tris.is_empty() || b.is_empty() {
            return;
        }
        let half = (b.max - o).abs().max((o - b.min).abs()).max_element();
        // The union absorbs the rounding of `o ± half`: the cube always holds the mesh.
        let cube = Aabb::new(o - Vec3::splat(half), o + Vec3::splat(half)).union(&b);
        out.push(OutlineBox { depth: 0, bounds: cube, leaf: true });
    }
}

#[cfg(test)]
mod tests {
    use crate::outline::checks::{self, Cover};
    use crate::{ABuffer, Accel, Apit, ApitParams};
    use dynray_geom::Vec3;

    #[test]
    fn outline_is_the_cube_around_the_observer() {
        let mesh = checks::mesh();
        let eye = Vec3::new(4.0, 1.0, 3.0);
        // The default observer is the mesh box's centre until an eye is given.
        for (params, observer) in
            [(ApitParams::fast(), mesh.bounds().center()), (ApitParams::default().with_observer(eye), eye)]
        {
            let apit = Apit::build(&mesh, &params).unwrap();
            let abuf = ABuffer::build(&mesh, &params).unwrap();
            for accel in [&apit as &dyn Accel, &abuf] {
                assert_eq!(checks::check(accel, &mesh, Cover::Centroids), 0, "{}", accel.name());
                let b = checks::outline(accel, 5)[0].bounds;
                let e = b.extent();
                assert!(e.max_element() - e.min_element() <= 1e-5 * e.max_element(), "{}: {e:?}", accel.name());
                let c = b.center();
                assert!((c - observer).length() < 1e-4, "{}: centre {c} for an observer at {observer}", accel.name());
                checks::appends(accel);
            }
            assert_eq!(checks::outline(&apit, 0), checks::outline(&abuf, 0));
        }
    }
}
