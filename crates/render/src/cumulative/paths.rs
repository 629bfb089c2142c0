//! The live paths of a wavefront, as flat arrays: one entry per path, the layout a GPU
//! kernel reads and appends to (structure of arrays, no pointers).

use crate::RayCone;
use dynray_geom::Ray;
use dynray_scene::Color;

/// A list of live paths: `ray[i]`, `cone[i]`, `product[i]`, `weight[i]`, `owner[i]` and
/// `id[i]` are path `i`.
#[derive(Clone, Debug, Default)]
pub(crate) struct Paths {
    /// The ray the path traces next: origin and direction (and its interval, which only
    /// camera rays may narrow).
    pub ray: Vec<Ray>,
    /// The ray's footprint (camera rays: their pixel's; children go on from the width it
    /// reached at their parent's hit), which filters the textures it sees.
    pub cone: Vec<RayCone>,
    /// `P`: the product of the coefficients along the path (divided by the choice
    /// probabilities past the branch depth), what `I(x)` at its next hit is scaled by.
    pub product: Vec<Color>,
    /// Whitted's weight of the ray (primary = 1, each child × its coefficient's largest
    /// component), for the `min_weight` rule; never divided by a probability.
    pub weight: Vec<f32>,
    /// Index of the camera sample in the batch whose sum `S` the path adds to.
    pub owner: Vec<u32>,
    /// The path's number within its sample's tree, which keys its choices
    /// ([`crate::choice_random`]): camera path 1; an expanded hit's `i`-th
    /// traced child `2 · id + i`; a chosen or only child keeps `id`. Unique per level
    /// up to 31 expanded levels (it wraps beyond: siblings then share numbers, which
    /// correlates them but biases nothing).
    pub id: Vec<u32>,
}

impl Paths {
    /// An empty list with room for `n` paths.
    pub fn with_capacity(n: usize) -> Self {
        Self {
            ray: Vec::with_capacity(n),
            cone: Vec::with_capacity(n),
            product: Vec::with_capacity(n),
            weight: Vec::with_capacity(n),
            owner: Vec::with_capacity(n),
            id: Vec::with_capacity(n),
        }
    }

    /// The camera rays as paths (footprints `cones[i]`): `P = 1`, weight 1, each its own
    /// sample.
    pub fn camera(&mut self, rays: &[Ray], cones: &[RayCone]) {
        self.clear();
        assert!(rays.len() <= u32::MAX as usize, "{} camera rays in one batch; owners are u32", rays.len());
        assert_eq!(rays.len(), cones.len(), "one cone per camera ray");
        for (i, (r, c)) in rays.iter().zip(cones).enumerate() {
            self.push(*r, *c, Color::ONE, 1.0, i as u32, 1);
        }
    }

    /// Number of live paths.
    pub fn len(&self) -> usize {
        self.ray.len()
    }

    /// Whether no path is live.
    pub fn is_empty(&self) -> bool {
        self.ray.is_empty()
    }

    /// Forgets every path, keeping the allocations.
    pub fn clear(&mut self) {
        self.ray.clear();
        self.cone.clear();
        self.product.clear();
        self.weight.clear();
        self.owner.clear();
        self.id.clear();
    }

    /// Appends a path.
    pub fn push(&mut self, ray: Ray, cone: RayCone, product: Color, weight: f32, owner: u32, id: u32) {
        self.ray.push(ray);
        self.cone.push(cone);
        self.product.push(product);
        self.weight.push(weight);
        self.owner.push(owner);
        self.id.push(id);
    }
}
