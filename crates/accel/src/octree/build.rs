//! Octree construction: midpoint subdivision of the scene cube, exact triangle–box
//! overlap (every leaf a triangle touches lists it), optional 2:1 face balance, then
//! serialisation of the leaves into the seed's word records, the box array, the cube
//! map of boundary leaves and the compact internal-node array.

use super::node::{InnerNode, LeafBox, LEAF_BIT, LOCATE};
use super::params::OctreeParams;
use super::tables::{in_face_axes, neighbor_slot, FACE_AXIS, FACE_POSITIVE};
use crate::BuildError;
use dynray_geom::triangle_box_overlap;
use dynray_geom::{Aabb, Triangle, TriangleMesh};
use glam::Vec3;
use rayon::prelude::*;

/// The root cube every cell box derives from.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    /// Smallest corner of the root cube.
    pub min: Vec3,
    /// Edge length of the root cube (> 0).
    pub size: f32,
}

impl Frame {
    /// Box of the cell `(x, y, z)` at `depth`. Each plane is `min + size·(q·2^-depth)`
    /// where `q·2^-depth` is exact, so a plane shared by cells of any depths has the same
    /// bits in all of them: adjacent leaves meet without gap or overlap.
    pub fn cell_box(&self, cell: [u32; 3], depth: u32) -> Aabb {
        let inv = 1.0 / (1u64 << depth) as f32;
        let plane = |a: usize, q: u32| self.min[a] + self.size * (q as f32 * inv);
        let lo = Vec3::new(plane(0, cell[0]), plane(1, cell[1]), plane(2, cell[2]));
        let hi = Vec3::new(plane(0, cell[0] + 1), plane(1, cell[1] + 1), plane(2, cell[2] + 1));
        Aabb::new(lo, hi)
    }
}

/// Node of the build tree (freed after serialisation).
struct BNode {
    cell: [u32; 3],
    depth: u32,
    /// First of eight consecutive children, or `NONE` for a leaf.
    first_child: u32,
    /// Triangles overlapping the cell (leaves only).
    tris: Vec<u32>,
}

const NONE: u32 = u32::MAX;

/// Neighbours of one leaf face, as leaf indices.
#[derive(Clone, Copy)]
enum Nbr {
    Boundary,
    One(u32),
    Four([u32; 4]),
    Locate,
}

/// Everything the builder produces.
pub(super) struct Built {
    pub records: Vec<u32>,
    pub boxes: Vec<LeafBox>,
    pub tris: Vec<Triangle>,
    pub prim_ids: Vec<u32>,
    pub inner: Vec<InnerNode>,
    pub root: u32,
    pub cube_map: Vec<u32>,
    pub cube_depth: u32,
    pub fine_depth: u32,
    pub frame: Frame,
    pub leaves_before_balance: usize,
    pub locate_faces: usize,
}

struct Builder<'a> {
    nodes: Vec<BNode>,
    frame: Frame,
    /// Outward widening of every cell box in the overlap test (see `build`).
    eps: f64,
    verts: &'a [[[f64; 3]; 3]],
    tri_lo: &'a [[f64; 3]],
    tri_hi: &'a [[f64; 3]],
}

impl Builder<'_> {
    /// Distributes node `n`'s triangles to its eight children without attaching them.
    fn child_lists(&self, n: usize) -> [Vec<u32>; 8] {
        let node = &self.nodes[n];
        let d = node.depth + 1;
        let base = [node.cell[0] * 2, node.cell[1] * 2, node.cell[2] * 2];
        let boxes: [(Aabb, [f64; 3], [f64; 3]); 8] = std::array::from_fn(|o| {
            let b = self
                .frame
                .cell_box([base[0] + (o as u32 & 1), base[1] + (o as u32 >> 1 & 1), base[2] + (o as u32 >> 2 & 1)], d);
            let c = b.center();
            let h = b.extent() * 0.5;
            (
                b,
                [c.x as f64, c.y as f64, c.z as f64],
                [h.x as f64 + self.eps, h.y as f64 + self.eps, h.z as f64 + self.eps],
            )
        });
        let mid = boxes[0].0.max;
        let mut out: [Vec<u32>; 8] = Default::default();
        for &t in &node.tris {
            let (lo, hi) = (self.tri_lo[t as usize], self.tri_hi[t as usize]);
            // Octant range of the triangle's box: cheap pre-filter before the SAT test.
            let side = |a: usize| {
                let m = mid[a] as f64;
                ((lo[a] <= m + self.eps) as u32, (hi[a] >= m - self.eps) as u32)
            };
            let (sx, sy, sz) = (side(0), side(1), side(2));
            for o in 0..8usize {
                let bits = [o & 1, o >> 1 & 1, o >> 2 & 1];
                let ok = |s: (u32, u32), b: usize| if b == 0 { s.0 == 1 } else { s.1 == 1 };
                if ok(sx, bits[0]) && ok(sy, bits[1]) && ok(sz, bits[2]) {
                    let (_, c, h) = boxes[o];
                    if triangle_box_overlap(&self.verts[t as usize], c, h) {
                        out[o].push(t);
                    }
                }
            }
        }
        out
    }

    /// Turns leaf `n` into an internal node with the given children lists.
    fn attach(&mut self, n: usize, lists: [Vec<u32>; 8]) {
        let first = self.nodes.len() as u32;
        let (cell, depth) = (self.nodes[n].cell, self.nodes[n].depth);
        for (o, tris) in lists.into_iter().enumerate() {
            let o = o as u32;
            self.nodes.push(BNode {
                cell: [cell[0] * 2 + (o & 1), cell[1] * 2 + (o >> 1 & 1), cell[2] * 2 + (o >> 2 & 1)],
                depth: depth + 1,
                first_child: NONE,
                tris,
            });
        }
        self.nodes[n].first_child = first;
        self.nodes[n].tris = Vec::new();
    }

    /// The node covering cell `cell` at `depth`: that cell itself if it exists, else the
    /// leaf that contains it.
    fn covering(&self, cell: [u32; 3], depth: u32) -> usize {
        let mut n = 0usize;
        loop {
            let node = &self.nodes[n];
            if node.first_child == NONE || node.depth == depth {
                return n;
            }
            let shift = depth - node.depth - 1;
            let o = (cell[0] >> shift & 1) | (cell[1] >> shift & 1) << 1 | (cell[2] >> shift & 1) << 2;
            n = (node.first_child + o) as usize;
        }
    }

    /// The same-size cell across face `f` of `(cell, depth)`, or `None` at the root boundary.
    fn across(cell: [u32; 3], depth: u32, f: usize) -> Option<[u32; 3]> {
        let a = FACE_AXIS[f];
        let mut c = cell;
        if FACE_POSITIVE[f] {
            c[a] += 1;
            if c[a] >= 1 << depth {
                return None;
            }
        } else {
            c[a] = c[a].checked_sub(1)?;
        }
        Some(c)
    }

    /// Refines until no leaf has a face neighbour two or more levels deeper: for each leaf,
    /// the leaf covering the same-size cell across each face must be at most one level
    /// shallower, and is split (triangles redistributed) until it is.
    fn balance(&mut self) {
        let mut queue: Vec<usize> = (0..self.nodes.len()).filter(|&n| self.nodes[n].first_child == NONE).collect();
        while let Some(l) = queue.pop() {
            let (cell, depth) = (self.nodes[l].cell, self.nodes[l].depth);
            if self.nodes[l].first_child != NONE || depth < 2 {
                continue;
            }
            for f in 0..6 {
                let Some(nc) = Self::across(cell, depth, f) else { continue };
                loop {
                    let m = self.covering(nc, depth);
                    if self.nodes[m].first_child != NONE || self.nodes[m].depth + 1 >= depth {
                        break;
                    }
                    let lists = self.child_lists(m);
                    self.attach(m, lists);
                    let first = self.nodes[m].first_child as usize;
                    queue.extend(first..first + 8);
                }
            }
        }
    }

    /// Neighbours across face `f` of leaf node `l`, as build-node indices.
    fn neighbors(&self, l: usize, f: usize) -> Nbr {
        let (cell, depth) = (self.nodes[l].cell, self.nodes[l].depth);
        let Some(nc) = Self::across(cell, depth, f) else { return Nbr::Boundary };
        let m = self.covering(nc, depth);
        let node = &self.nodes[m];
        if node.first_child == NONE {
            return Nbr::One(m as u32);
        }
        // Same-size cell is subdivided: its four children on the near side of the face.
        let a = FACE_AXIS[f];
        let near_bit = if FACE_POSITIVE[f] { 0 } else { 1 };
        let (u, w) = in_face_axes(f);
        let mut four = [0u32; 4];
        for (bu, bw) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            let o = (near_bit << a) | (bu << u) | (bw << w);
            let c = node.first_child + o as u32;
            if self.nodes[c as usize].first_child != NONE {
                return Nbr::Locate;
            }
            four[neighbor_slot(bu == 1, bw == 1)] = c;
        }
        Nbr::Four(four)
    }
}

/// Builds the octree over `mesh` (already validated).
pub(super) fn build(mesh: &TriangleMesh, params: &OctreeParams) -> Result<Built, BuildError> {
    let n_tris = mesh.triangle_count();
    if n_tris >= LEAF_BIT as usize {
        return Err(BuildError::Limit(format!("{n_tris} triangles exceed the octree's 2^31 limit")));
    }
    let bounds = mesh.bounds();
    let frame = root_frame(&bounds);
    let tri_list: Vec<Triangle> = mesh.triangles().collect();
    let to64 = |p: Vec3| [p.x as f64, p.y as f64, p.z as f64];
    let verts: Vec<[[f64; 3]; 3]> = tri_list.iter().map(|t| [to64(t.p0), to64(t.p1), to64(t.p2)]).collect();
    let tri_lo: Vec<[f64; 3]> = tri_list.iter().map(|t| to64(t.bounds().min)).collect();
    let tri_hi: Vec<[f64; 3]> = tri_list.iter().map(|t| to64(t.bounds().max)).collect();
    // Cell boxes are widened by this much in the overlap test. It must dwarf the rounding
    // of the traversal's float arithmetic (slab distances, exit points: a few ulps of the
    // coordinates), because a ray that the walk steers through a neighbouring cell within
    // rounding of an edge still finds every triangle it hits there. 2^-17 of the scene's
    // coordinate magnitude is ~100 ulps, and adds a fraction of a percent of references.
    let magnitude = frame.size as f64 + bounds.min.abs().max(bounds.max.abs()).max_element() as f64;
    let eps = magnitude * (2f64).powi(-17);
    let mut b = Builder { nodes: Vec::new(), frame, eps, verts: &verts, tri_lo: &tri_lo, tri_hi: &tri_hi };
    b.nodes.push(BNode { cell: [0; 3], depth: 0, first_child: NONE, tris: (0..n_tris as u32).collect() });

    // Subdivision, level by level so that the overlap tests of a whole level run in
    // parallel. A split where some child keeps all of the parent's
    // triangles reduces nothing ("bad", as pbrt's kd-tree calls it): it is allowed at most
    // twice on a path and only when it at most doubles the references, so identical or
    // huge overlapping triangles cannot multiply without bound; a global reference budget
    // is the last guard on pathological inputs.
    let budget = 64 * n_tris + (1 << 20);
    let mut refs = n_tris;
    let mut frontier = vec![(0usize, 0u32)];
    while !frontier.is_empty() {
        frontier.retain(|&(n, _)| {
            let node = &b.nodes[n];
            node.depth < params.max_depth && node.tris.len() > params.leaf_threshold as usize
        });
        let splits: Vec<Option<([Vec<u32>; 8], bool)>> = frontier
            .par_iter()
            .map(|&(n, bad)| {
                let count = b.nodes[n].tris.len();
                let lists = b.child_lists(n);
                let total: usize = lists.iter().map(Vec::len).sum();
                let good = lists.iter().all(|l| l.len() < count);
                (good || (bad < 2 && total <= 2 * count)).then_some((lists, good))
            })
            .collect();
        let mut next = Vec::new();
        for (&(n, bad), split) in frontier.iter().zip(splits) {
            let Some((lists, good)) = split else { continue };
            if refs > budget {
                break;
            }
            refs += lists.iter().map(Vec::len).sum::<usize>() - b.nodes[n].tris.len();
            let first = b.nodes.len();
            b.attach(n, lists);
            next.extend((first..first + 8).map(|c| (c, bad + !good as u32)));
        }
        frontier = next;
    }
    let leaves_before_balance = b.nodes.iter().filter(|n| n.first_child == NONE).count();
    if params.balance {
        b.balance();
    }
    serialise(&b, frame, leaves_before_balance)
}

/// The scene box made cubic, padded so every vertex lies strictly inside, with a floor on
/// the size so a mesh collapsed to a point still gets a usable cube.
fn root_frame(bounds: &Aabb) -> Frame {
    let magnitude = bounds.min.abs().max(bounds.max.abs()).max_element();
    let size = bounds.extent().max_element().max(magnitude * 1e-5).max(1e-20);
    let pad = size * (1.0 / 65536.0);
    let mut frame = Frame { min: bounds.min - Vec3::splat(pad), size: size + 2.0 * pad };
    // Rounding of `min + size` cannot undercut the mesh by a 2^-16 margin, but make sure.
    while frame.cell_box([0; 3], 0).max.cmplt(bounds.max).any() {
        frame.size *= 1.0 + 1.0 / 1024.0;
    }
    frame
}

fn serialise(b: &Builder, frame: Frame, leaves_before_balance: usize) -> Result<Built, BuildError> {
    // Leaves and internal nodes in depth-first order (children in octant order): leaves
    // that are close in space are close in memory.
    let mut leaf_of = vec![NONE; b.nodes.len()];
    let mut inner_of = vec![NONE; b.nodes.len()];
    let mut leaves = Vec::new();
    let mut inners = Vec::new();
    let mut stack = vec![0usize];
    while let Some(n) = stack.pop() {
        let node = &b.nodes[n];
        if node.first_child == NONE {
            leaf_of[n] = leaves.len() as u32;
            leaves.push(n);
        } else {
            inner_of[n] = inners.len() as u32;
            inners.push(n);
            stack.extend((node.first_child as usize..node.first_child as usize + 8).rev());
        }
    }
    let nbrs: Vec<[Nbr; 6]> = leaves.par_iter().map(|&l| std::array::from_fn(|f| b.neighbors(l, f))).collect();
    let words = |nb: &[Nbr; 6]| {
        4 + nb
            .iter()
            .map(|n| {
                if let Nbr::One(_) = n {
                    1
                } else if let Nbr::Four(_) = n {
                    4
                } else {
                    0
                }
            })
            .sum::<usize>()
    };
    let mut addr = Vec::with_capacity(leaves.len());
    let mut total = 0usize;
    for nb in &nbrs {
        addr.push(total as u32);
        total += words(nb);
    }
    if total >= LEAF_BIT as usize {
        return Err(BuildError::Limit(format!("octree records need {total} words, more than 2^31")));
    }
    let n_refs: usize = leaves.iter().map(|&l| b.nodes[l].tris.len()).sum();
    if n_refs >= u32::MAX as usize {
        return Err(BuildError::Limit(format!("{n_refs} triangle references exceed u32")));
    }
    let mut records = Vec::with_capacity(total);
    let mut boxes = Vec::with_capacity(leaves.len());
    let mut prim_ids = Vec::with_capacity(n_refs);
    let mut locate_faces = 0;
    let addr_of = |node: u32| addr[leaf_of[node as usize] as usize];
    for (i, (&l, nb)) in leaves.iter().zip(&nbrs).enumerate() {
        let node = &b.nodes[l];
        let mut tris = node.tris.clone();
        tris.sort_unstable();
        records.extend([tris.len() as u32, prim_ids.len() as u32, i as u32, 0]);
        prim_ids.extend_from_slice(&tris);
        let mut n_count = 0u32;
        for (f, n) in nb.iter().enumerate() {
            let nib = match *n {
                Nbr::Boundary => 0,
                Nbr::One(m) => {
                    records.push(addr_of(m));
                    1
                }
                Nbr::Four(ms) => {
                    records.extend(ms.iter().map(|&m| addr_of(m)));
                    4
                }
                Nbr::Locate => {
                    locate_faces += 1;
                    LOCATE
                }
            };
            n_count |= nib << (4 * f);
        }
        records[addr[i] as usize + 3] = n_count;
        let bx = frame.cell_box(node.cell, node.depth);
        let c16 = |v: u32| u16::try_from(v).expect("depth <= MAX_DEPTH_LIMIT keeps cells in 16 bits");
        boxes.push(LeafBox {
            min: bx.min,
            max: bx.max,
            cell: [c16(node.cell[0]), c16(node.cell[1]), c16(node.cell[2]), c16(node.depth)],
        });
    }
    let tris = prim_ids.iter().map(|&t| triangle_of(b, t)).collect();
    let child_ref = |n: usize| if b.nodes[n].first_child == NONE { LEAF_BIT | addr_of(n as u32) } else { inner_of[n] };
    let inner: Vec<InnerNode> = inners
        .iter()
        .map(|&n| InnerNode { child: std::array::from_fn(|o| child_ref(b.nodes[n].first_child as usize + o)) })
        .collect();
    let root = child_ref(0);
    let fine_depth = leaves.iter().map(|&l| b.nodes[l].depth).max().unwrap_or(0);
    let (cube_map, cube_depth) = cube_map(b, &leaves, &addr);
    Ok(Built {
        records,
        boxes,
        tris,
        prim_ids,
        inner,
        root,
        cube_map,
        cube_depth,
        fine_depth,
        frame,
        leaves_before_balance,
        locate_faces,
    })
}

fn triangle_of(b: &Builder, t: u32) -> Triangle {
    // The f64 copies were widened from these f32 values: narrowing is exact.
    let v = b.verts[t as usize];
    let p = |i: usize| Vec3::new(v[i][0] as f32, v[i][1] as f32, v[i][2] as f32);
    Triangle::new(p(0), p(1), p(2))
}

/// One address per texel of the six root faces at the finest depth of any leaf that
/// touches the root boundary, so each texel lies in exactly one boundary leaf.
/// Layout: `face · R² + w · R + u`, `(u, w)` the face's in-face axes, `R = 2^cube_depth`.
fn cube_map(b: &Builder, leaves: &[usize], addr: &[u32]) -> (Vec<u32>, u32) {
    let on_boundary = |n: &BNode| {
        let last = (1u32 << n.depth) - 1;
        n.cell.iter().any(|&c| c == 0 || c == last)
    };
    let depth = leaves.iter().map(|&l| &b.nodes[l]).filter(|n| on_boundary(n)).map(|n| n.depth).max().unwrap_or(0);
    let r = 1u32 << depth;
    let mut leaf_index = vec![NONE; b.nodes.len()];
    for (i, &l) in leaves.iter().enumerate() {
        leaf_index[l] = i as u32;
    }
    let map: Vec<u32> = (0..6 * r)
        .into_par_iter()
        .flat_map_iter(|row| {
            let (f, tw) = ((row / r) as usize, row % r);
            let a = FACE_AXIS[f];
            let (u, w) = in_face_axes(f);
            let leaf_index = &leaf_index;
            (0..r).map(move |tu| {
                let mut cell = [0u32; 3];
                cell[a] = if FACE_POSITIVE[f] { r - 1 } else { 0 };
                cell[u] = tu;
                cell[w] = tw;
                let n = b.covering(cell, depth);
                debug_assert_eq!(b.nodes[n].first_child, NONE, "boundary cells are no deeper than the cube map");
                addr[leaf_index[n] as usize]
            })
        })
        .collect();
    (map, depth)
}
