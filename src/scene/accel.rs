//! Ray queries over all primitives: an obvhs compressed-wide BVH (CWBVH, Ylitie et al.
//! 2017) with our own exact primitive tests in its callbacks, or a plain loop for
//! scenes of a handful of primitives, where a BVH only costs.
//!
//! obvhs hands the callback a *slot*, which indexes `bvh.primitive_indices`, not our
//! primitive list (STACK.md): the primitives are copied once into slot order, each with
//! its index, so a leaf reads its primitives contiguously. Shadow rays use
//! `ray_traverse_miss`, which stops at the first hit.

use crate::scene::shape::{Hit, Primitive};
use glam::{Vec3, Vec3A};
use obvhs::aabb::Aabb;
use obvhs::cwbvh::CwBvh;
use obvhs::ray::{Ray, RayHit};

/// Below this many primitives, rays test every primitive.
const LINEAR_LIMIT: usize = 8;

/// The direction handed to obvhs, with every −0.0 component made +0.0: obvhs 0.4's
/// CWBVH traversal misses boxes for directions holding −0.0 (measured: a ray along
/// (−1, −0, −0) from inside a closed box mesh found no face; found by the mean-chord
/// case, whose cosine directions about an axis-aligned normal carry −0.0). Adding +0.0
/// maps −0.0 to +0.0 and leaves every other value unchanged; the primitive tests still
/// use the caller's direction.
#[inline]
fn obvhs_direction(d: Vec3) -> Vec3A {
    Vec3A::from(d) + Vec3A::ZERO
}

/// A primitive in BVH order: what a leaf's callback reads, contiguous for the
/// primitives of one leaf (no look-up through `primitive_indices`, one cache line or two
/// per leaf instead of a random access per primitive; the same tests in the same order).
#[derive(Clone, Copy, Debug)]
struct Slot {
    /// The primitive.
    prim: Primitive,
    /// Its index in [`Accel::prims`].
    index: u32,
    /// Whether the queries skip it (a moving shape's).
    skip: bool,
}

/// The BVH and its primitives in slot order.
struct Tree {
    bvh: CwBvh,
    slots: Vec<Slot>,
}

/// Acceleration structure over primitives.
pub struct Accel {
    prims: Vec<Primitive>,
    tree: Option<Tree>,
    /// Primitives the queries skip (moving shapes, which the scene tests itself).
    skip: Vec<bool>,
}

impl Accel {
    /// Build over `prims`.
    pub fn new(prims: Vec<Primitive>) -> Self {
        let tree = (prims.len() > LINEAR_LIMIT).then(|| {
            let aabbs: Vec<Aabb> = prims
                .iter()
                .map(|p| {
                    let (lo, hi) = p.bounds();
                    Aabb::new(Vec3A::from(lo), Vec3A::from(hi))
                })
                .collect();
            let mut t = std::time::Duration::default();
            // The build preset matters little here: on the 100k-triangle bench sphere,
            // `slow`, `very_slow` and leaves of 1, 2 or 4 primitives were all within the
            // noise of `medium` (0.6–0.85 M closest hits per CPU second, 3.6–4.3
            // primitive tests per ray), and `medium` builds 4× faster than `very_slow`.
            let bvh = obvhs::cwbvh::builder::build_cwbvh(
                &aabbs,
                obvhs::BvhBuildParams::medium_build(),
                &mut t,
            );
            let slots = bvh
                .primitive_indices
                .iter()
                .map(|&i| Slot {
                    prim: prims[i as usize],
                    index: i,
                    skip: false,
                })
                .collect();
            Tree { bvh, slots }
        });
        let skip = vec![false; prims.len()];
        Accel { prims, tree, skip }
    }

    /// Make the queries skip the primitives marked `true` (moving shapes).
    pub fn set_skip(&mut self, skip: Vec<bool>) {
        assert_eq!(skip.len(), self.prims.len());
        if let Some(tree) = &mut self.tree {
            for slot in &mut tree.slots {
                slot.skip = skip[slot.index as usize];
            }
        }
        self.skip = skip;
    }

    /// The primitives.
    pub fn prims(&self) -> &[Primitive] {
        &self.prims
    }

    /// Closest hit with t in (tmin, tmax): (primitive index, hit).
    pub fn intersect(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> Option<(usize, Hit)> {
        match &self.tree {
            None => {
                let mut best: Option<(usize, Hit)> = None;
                let mut tm = tmax;
                for (i, p) in self.prims.iter().enumerate() {
                    if self.skip[i] {
                        continue;
                    }
                    if let Some(h) = p.intersect(o, d, tmin, tm) {
                        tm = h.t;
                        best = Some((i, h));
                    }
                }
                best
            }
            Some(Tree { bvh, slots }) => {
                let ray = Ray::new(Vec3A::from(o), obvhs_direction(d), tmin, tmax);
                let mut hit = RayHit::none();
                let mut best: Option<(usize, Hit)> = None;
                bvh.ray_traverse(ray, &mut hit, |r, slot| {
                    let s = &slots[slot];
                    if s.skip {
                        return f32::INFINITY;
                    }
                    match s.prim.intersect(o, d, tmin, r.tmax) {
                        Some(h) => {
                            best = Some((s.index as usize, h));
                            h.t
                        }
                        None => f32::INFINITY,
                    }
                });
                best
            }
        }
    }

    /// Whether nothing lies on the segment t ∈ (tmin, tmax).
    pub fn unoccluded(&self, o: Vec3, d: Vec3, tmin: f32, tmax: f32) -> bool {
        match &self.tree {
            None => self
                .prims
                .iter()
                .zip(&self.skip)
                .all(|(p, &skip)| skip || p.intersect(o, d, tmin, tmax).is_none()),
            Some(Tree { bvh, slots }) => {
                let ray = Ray::new(Vec3A::from(o), obvhs_direction(d), tmin, tmax);
                bvh.ray_traverse_miss(ray, |_, slot| {
                    let s = &slots[slot];
                    if s.skip {
                        return f32::INFINITY;
                    }
                    s.prim
                        .intersect(o, d, tmin, tmax)
                        .map_or(f32::INFINITY, |h| h.t)
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Sampler;
    use crate::sampling::sphere::uniform_sphere;

    #[test]
    fn negative_zero_directions_find_the_box() {
        // A closed 1 × 2 × 3 box of 12 triangles (a BVH), rays from inside along the axes
        // with −0.0 in the other components.
        let v = [
            [0., 0., 0.],
            [1., 0., 0.],
            [1., 2., 0.],
            [0., 2., 0.],
            [0., 0., 3.],
            [1., 0., 3.],
            [1., 2., 3.],
            [0., 2., 3.],
        ]
        .map(Vec3::from_array);
        let tris = [
            [0, 2, 1],
            [0, 3, 2],
            [4, 5, 6],
            [4, 6, 7],
            [0, 1, 5],
            [0, 5, 4],
            [3, 7, 6],
            [3, 6, 2],
            [0, 4, 7],
            [0, 7, 3],
            [1, 2, 6],
            [1, 6, 5],
        ];
        let prims: Vec<Primitive> = tris
            .iter()
            .map(|t| Primitive::Triangle {
                p: [v[t[0]], v[t[1]], v[t[2]]],
            })
            .collect();
        let accel = Accel::new(prims);
        assert!(accel.tree.is_some());
        let o = Vec3::new(0.5, 1.0, 1.5);
        for d in [
            Vec3::new(-1.0, -0.0, -0.0),
            Vec3::new(1.0, -0.0, 0.0),
            Vec3::new(-0.0, -1.0, -0.0),
            Vec3::new(-0.0, -0.0, -1.0),
            Vec3::new(0.0, 0.0, 1.0),
        ] {
            assert!(accel.intersect(o, d, 0.0, f32::INFINITY).is_some(), "{d:?}");
            assert!(!accel.unoccluded(o, d, 0.0, f32::INFINITY), "{d:?}");
        }
    }

    #[test]
    fn skipped_primitives_are_not_hit_through_the_bvh() {
        // Twelve spheres on the z axis; skipping the nearest makes the next one the hit.
        let prims: Vec<Primitive> = (0..12)
            .map(|i| Primitive::Sphere {
                center: Vec3::new(0.0, 0.0, 3.0 * (i + 1) as f32),
                radius: 1.0,
            })
            .collect();
        let mut accel = Accel::new(prims);
        assert!(accel.tree.is_some());
        let hit = |a: &Accel| a.intersect(Vec3::ZERO, Vec3::Z, 0.0, f32::INFINITY);
        assert_eq!(hit(&accel).map(|h| h.0), Some(0));
        let mut skip = vec![false; 12];
        skip[0] = true;
        accel.set_skip(skip);
        assert_eq!(hit(&accel).map(|h| h.0), Some(1));
        assert!(accel.unoccluded(Vec3::ZERO, Vec3::Z, 0.0, 4.5));
        assert!(!accel.unoccluded(Vec3::ZERO, Vec3::Z, 0.0, 5.5));
    }

    #[test]
    fn bvh_agrees_with_brute_force() {
        let sampler = Sampler::independent(5);
        let mut prims = Vec::new();
        for i in 0..200u64 {
            let mut s = sampler.stream(i);
            let c = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 10.0;
            if i % 2 == 0 {
                prims.push(Primitive::Sphere {
                    center: c,
                    radius: 0.3,
                });
            } else {
                let a = uniform_sphere(s.next_2d());
                let b = uniform_sphere(s.next_2d());
                prims.push(Primitive::Triangle {
                    p: [c, c + a, c + b],
                });
            }
        }
        let accel = Accel::new(prims.clone());
        assert!(accel.tree.is_some());
        for i in 0..2000u64 {
            let mut s = sampler.stream(10_000 + i);
            let o = Vec3::new(s.next_1d(), s.next_1d(), s.next_1d()) * 10.0;
            let d = uniform_sphere(s.next_2d());
            let fast = accel
                .intersect(o, d, 0.0, f32::INFINITY)
                .map(|(i, h)| (i, h.t));
            let mut slow: Option<(usize, f32)> = None;
            for (k, p) in prims.iter().enumerate() {
                if let Some(h) = p.intersect(o, d, 0.0, slow.map_or(f32::INFINITY, |x| x.1)) {
                    slow = Some((k, h.t));
                }
            }
            assert_eq!(fast, slow);
            assert_eq!(
                accel.unoccluded(o, d, 0.0, 5.0),
                slow.is_none_or(|x| x.1 >= 5.0)
            );
        }
    }
}
