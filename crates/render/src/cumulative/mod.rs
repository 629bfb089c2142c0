//! Seed 004's cumulative ("acumulativo") ray tracer: Whitted's image without recursion,
//! in the shape a GPU kernel takes (seed 004 §2.7, Eq. 4–5 and the step equations).
//!
//! Whitted's radiance along a ray is `L(x) = I(x) + Σ_c R_c(x) · L(x_c)`: the local term
//! (ambient, lights through shadow rays) plus, for each child `c` (mirror reflection,
//! refraction), its coefficient times the child's radiance. Unrolled along one path
//! `x_0, x_1, …` it is a running product and a running sum:
//!
//! ```text
//! P_0 = 1,  S_0 = I(x_0),   P_k = P_{k-1} · R(x_{k-1}),   S_k = S_{k-1} + P_k · I(x_k)
//! ```
//!
//! so a path needs only its ray, `P` and the sum `S` of its camera sample, never a stack.
//! Each batch of camera rays (one tile's samples, from the render loop) is traced as a
//! wavefront:
//!
//! - `paths.rs` holds the live paths in flat arrays (ray origin and direction, `P`,
//!   Whitted's weight, and the index of the camera sample whose `S` it adds to); the
//!   sums `S` are one array per batch, one entry per camera sample.
//! - `bounce.rs` is one pass over every live path: intersect, add `P · I(x)` to its
//!   sample's `S`, and write the children that go on into the next list. Paths that
//!   miss, reach `max_recursion_level`, or whose children fall under `min_weight` are
//!   not written, so the next list is dense (compaction: a GPU's append buffer); the
//!   passes ping-pong between two lists until none is live.
//!
//! Branching. For the first `K` bounces (`--branch-depth`, hits of rays of level `≤ K`)
//! every reflection/refraction pair is expanded: the path splits into both children,
//! each with `P · R_c`. Past `K` a hit with two children continues into one, chosen at
//! random with probability `p_c = w_c / (w_r + w_t)`, `w_c` the largest component of the
//! child's coefficient (the quantity Whitted's weight rule uses); for glass, whose mirror
//! coefficient is the Fresnel reflectance `F` (times its transparency) and whose
//! refraction coefficient is `1 − F`, that is a choice by Fresnel, as the seed says
//! (exact Fresnel as Whitted's, not Schlick's approximation, so that the expected image
//! is Whitted's and not an approximation of it). The chosen child carries
//! `P · R_c / p_c`. A hit with one child (a mirror, total internal reflection) continues
//! into it without a draw.
//!
//! Why the expected value is Whitted's: at a chosen hit the estimate of the children's
//! part is `R_c L_c / p_c` with probability `p_c`, whose expectation is
//! `Σ_c p_c · R_c L_c / p_c = Σ_c R_c L_c`, Whitted's sum, provided every `p_c > 0`
//! where `R_c L_c ≠ 0` (true: a child that passes the weight rule has `w_c > 0`). The
//! stopping rules are Whitted's own: the level limit is the pass count, and a child is
//! traced only when *Whitted's* weight (parent weight × `w_c`, not divided by `p_c`)
//! exceeds `min_weight`, so a chosen child is traced exactly when Whitted would trace
//! it. By induction over the bounces the expected `S` of a camera sample is Whitted's
//! radiance of that ray, so passes ([`crate::RenderOptions::passes`]) converge to
//! Whitted's image. Dividing by `p_c` rather than adding nothing also keeps the
//! estimate bounded: for clear glass `R_r/p_r = R_t/p_t = transparency`.
//!
//! With `K ≥ max_recursion_level − 1` nothing is ever chosen: the paths are exactly
//! Whitted's ray tree, every local term is computed by the same code (`shading.rs`) on
//! the same rays, and the image equals Whitted's up to the order of floating-point
//! operations (Whitted nests `I₀ + R₁(I₁ + R₂ I₂)`, the sum here is
//! `I₀ + R₁I₁ + (R₁R₂)I₂`), a relative difference of a few units in the last place per
//! term; the shadow and secondary ray counts are equal.
//!
//! Random numbers: each camera sample draws one `u32` from its [`crate::Sampler`], its
//! key, and the choice at the hit of path `id` (module `paths`: camera path 1, an
//! expanded hit's children `2·id`, `2·id + 1`, a chosen child keeps `id`) on ray level
//! `level` compares [`crate::choice_random`]`(key, level, id)` with the
//! reflection's probability. The number is a stateless integer hash, so it depends
//! neither on the order of the lists nor on the other samples of the batch (images do
//! not depend on threads, tiles or batch sizes), and the GPU's wavefront kernel
//! (crates/gpu, docs/gpu.md) computes the same bits and chooses the same children.

mod bounce;
mod paths;
mod tracer;

pub use tracer::{Cumulative, DEFAULT_BRANCH_DEPTH, MAX_LIVE_PATHS};
