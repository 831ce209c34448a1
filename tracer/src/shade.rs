//! Whitted shading: Phong local illumination with shadow rays, plus recursive mirror
//! reflection and Snell refraction (Whitted 1980, "An improved illumination model for
//! shaded display").
//!
//! $I = K_a I_a C + \sum_{l} (K_d C I_l (L \cdot N) + K_s I_l (R \cdot V)^n) + K_r I_r + K_t C I_t$
//! over the visible lights $l$, with $R = 2N(N \cdot L) - L$ the mirrored light direction.
//! Escaping rays see the background colour.

use crate::arith::Arith;
use crate::effects::{has, ADAPTIVE, REFLECTION, REFRACTION, SHADOWS, SPECULAR};
use crate::float::Float;
use crate::geometry::{offset_ray, offset_ray_from, NO_HINT};
use crate::ray::{Hit, Ray};
use crate::stats::RayCounts;
use crate::world::{Light, Material, Scene};

pub use crate::settings::TraceLimits;
use std::cell::Cell;
use vecexpr::{Expr, Real, Vec3};

/// Traces `ray` at `depth` (1 for eye rays) with accumulated `weight`, returning its
/// radiance and counting the secondary rays it spawns: the instance compiled for the
/// effect set `FX` (see [`crate::effects`]), which must contain the effects the scene
/// and `limits` need ([`crate::effects::EffectSet::required`]); every such instance
/// returns what the general one (`FX` = [`crate::effects::ALL`]) returns, bit for bit,
/// and counts the same rays.
pub fn trace_fx<T: Float, const FX: u32>(
    scene: &Scene<T>,
    ray: &Ray<T>,
    depth: u32,
    weight: T,
    limits: &TraceLimits<T>,
    counts: &mut RayCounts,
) -> Vec3<T> {
    match scene.intersect_kinds::<FX>(ray) {
        Some(hit) => shade_fx::<T, FX>(scene, ray, &hit, depth, weight, limits, counts),
        None => scene.background,
    }
}

/// Local illumination plus the recursive terms at `hit` of `ray`, compiled for the
/// effect set `FX` under the contract of [`trace_fx`]: the light loop, the highlight, the reflection and the refraction ray are only compiled
/// in when `FX` has them.
#[allow(clippy::too_many_arguments)]
pub fn shade_fx<T: Float, const FX: u32>(
    scene: &Scene<T>,
    ray: &Ray<T>,
    hit: &Hit<T>,
    depth: u32,
    weight: T,
    limits: &TraceLimits<T>,
    counts: &mut RayCounts,
) -> Vec3<T> {
    // The local light, then each secondary ray traced and its radiance added in turn.
    let (mut color, spawned) = shade_local::<T, FX>(scene, ray, hit, depth, weight, limits, counts);
    for s in spawned.iter().flatten() {
        let c = trace_fx::<T, FX>(scene, &s.ray, depth + 1, s.weight, limits, counts);
        s.add_to(&mut color, &c, &limits.arith);
    }
    color
}

/// The geometric and shading normals at `hit` faced toward the incoming direction `d`,
/// and whether the ray enters the surface.
#[inline(always)]
fn facing<T: Real>(hit: &Hit<T>, d: &Vec3<T>) -> (bool, Vec3<T>, Vec3<T>) {
    // Every surface is two-sided.
    let entering = hit.geometric_normal.dot(d) < T::ZERO;
    if entering {
        (entering, hit.geometric_normal, hit.shading_normal)
    } else {
        (
            entering,
            (-&hit.geometric_normal).eval(),
            (-&hit.shading_normal).eval(),
        )
    }
}

/// A secondary ray spawned by the shading of a hit, and how its radiance joins the
/// hit's colour ([`Secondary::add_to`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Secondary<T: Real> {
    /// The ray, from the offset hit point.
    pub ray: Ray<T>,
    /// Its accumulated weight, for adaptive termination.
    pub weight: T,
    /// The factor of its radiance: $K_t$ or $K_r$.
    k: T,
    /// The surface colour a refracted ray's radiance is filtered by; `None` for a
    /// reflection.
    filter: Option<Vec3<T>>,
}

impl<T: Real> Secondary<T> {
    /// Adds radiance `c` of this ray to `color`, the colour of the hit that spawned it:
    /// $K_t C I_t$ or $K_r I_r$.
    #[inline(always)]
    pub(crate) fn add_to(&self, color: &mut Vec3<T>, c: &Vec3<T>, ar: &crate::arith::Arith) {
        match &self.filter {
            Some(f) => ar.add_scaled(color, &(c * f).eval(), self.k),
            None => ar.add_scaled(color, c, self.k),
        }
    }
}

/// The local illumination at `hit` of `ray` (ambient and the lights, with their shadow
/// rays, each traced here) and the secondary rays it spawns, refraction first: what
/// [`shade_fx`] computes before it traces them, and the rays it counts. The colour of
/// the hit is the local colour with the radiance of each secondary ray added in turn by
/// [`Secondary::add_to`]. The steps are [`Surface`]'s, which the packet renderer takes
/// one light at a time over a packet of hits ([`crate::packets`]).
#[inline(always)]
pub(crate) fn shade_local<T: Float, const FX: u32>(
    scene: &Scene<T>,
    ray: &Ray<T>,
    hit: &Hit<T>,
    depth: u32,
    weight: T,
    limits: &TraceLimits<T>,
    counts: &mut RayCounts,
) -> (Vec3<T>, [Option<Secondary<T>>; 2]) {
    let s = Surface::new(scene, ray, hit);
    let mut color = s.ambient();
    s.add_lights::<FX>(&mut color, scene, hit, depth, limits, counts);
    let spawned = s.spawn::<FX>(ray, hit, depth, weight, limits, counts);
    (color, spawned)
}

/// The shading of one hit, step by step: [`Surface::ambient`], then for each light
/// [`Surface::light_ray`] and, when its shadow ray is not blocked,
/// [`Surface::add_light`], then [`Surface::spawn`] ([`shade_local`] in that order).
pub(crate) struct Surface<'a, T: Real> {
    m: &'a Material<T>,
    /// Does the ray enter the surface?
    entering: bool,
    /// Geometric and shading normals, faced toward the ray.
    ng: Vec3<T>,
    ns: Vec3<T>,
    /// Toward the viewer: the ray's direction reversed.
    v: Vec3<T>,
    /// Where shadow rays start: the hit point offset along `ng`.
    above: Vec3<T>,
}

impl<'a, T: Real> Surface<'a, T> {
    /// The surface of `scene` at `hit` of `ray`.
    #[inline(always)]
    pub(crate) fn new(scene: &'a Scene<T>, ray: &Ray<T>, hit: &Hit<T>) -> Self {
        let (entering, ng, ns) = facing(hit, &ray.dir);
        let above = offset_ray(&hit.point, &ng, &ng);
        Self {
            m: &scene.materials[hit.material as usize],
            entering,
            ng,
            ns,
            v: (-&ray.dir).eval(),
            above,
        }
    }

    /// The ambient term $K_a C$, where the colour starts.
    #[inline(always)]
    pub(crate) fn ambient(&self) -> Vec3<T> {
        (&self.m.color).scale(self.m.ka).eval()
    }

    /// The shadow ray from the surface at `hit` toward `light` and the unit direction to
    /// the light, or `None` when shading casts none: a light without intensity, at the
    /// point itself, or behind the surface.
    #[inline(always)]
    pub(crate) fn light_ray(
        &self,
        light: &Light<T>,
        hit: &Hit<T>,
        ar: &Arith,
    ) -> Option<(Ray<T>, Vec3<T>)> {
        if light.intensity.max_element() <= T::ZERO {
            return None;
        }
        let to_light = (&light.position - &hit.point).eval();
        let (l, dist) = ar.unit_and_length(&to_light);
        if dist.is_nan() || dist <= T::ZERO || self.ng.dot(&l) <= T::ZERO {
            return None;
        }
        let shadow = Ray {
            t_max: dist,
            ..Ray::new(self.above, l)
        };
        Some((shadow, l))
    }

    /// Adds the terms of every light of `scene` whose shadow ray is not blocked to
    /// `color` (with `FX`'s shadows), tracing each shadow ray singly, with the shadow
    /// cache of the hit's ray depth `depth`.
    #[inline(always)]
    pub(crate) fn add_lights<const FX: u32>(
        &self,
        color: &mut Vec3<T>,
        scene: &Scene<T>,
        hit: &Hit<T>,
        depth: u32,
        limits: &TraceLimits<T>,
        counts: &mut RayCounts,
    ) where
        T: Float,
    {
        if !has(FX, SHADOWS) {
            return;
        }
        for (li, light) in scene.lights.iter().enumerate() {
            let Some((shadow, l)) = self.light_ray(light, hit, &limits.arith) else {
                continue;
            };
            counts.shadow += 1;
            if !occluded_cached::<T, FX>(scene, &shadow, depth, li) {
                self.add_light::<FX>(color, light, &l, &limits.arith);
            }
        }
    }

    /// Adds the diffuse and highlight terms of `light`, seen along the unit direction
    /// `l` ([`Surface::light_ray`]) by a shadow ray that nothing blocks, to `color`.
    #[inline(always)]
    pub(crate) fn add_light<const FX: u32>(
        &self,
        color: &mut Vec3<T>,
        light: &Light<T>,
        l: &Vec3<T>,
        ar: &Arith,
    ) {
        let m = self.m;
        let ndotl = ar.dot(&self.ns, l).max(T::ZERO);
        if m.kd > T::ZERO && ndotl > T::ZERO {
            let c = (&m.color * &light.intensity).eval();
            ar.add_scaled(color, &c, m.kd * ndotl);
        }
        if has(FX, SPECULAR) && m.ks > T::ZERO {
            // R = 2 N (N·L) - L, the mirror direction of the light.
            let r = ar.reflect(&(-l).eval(), &self.ns);
            let rv = ar.dot(&r, &self.v);
            if rv > T::ZERO {
                ar.add_scaled(color, &light.intensity, m.ks * ar.pow(rv, m.shine));
            }
        }
    }

    /// The secondary rays the hit spawns at `depth` with accumulated `weight`,
    /// refraction first (total internal reflection moves its weight to the reflection
    /// ray), counted in `counts`.
    #[inline(always)]
    pub(crate) fn spawn<const FX: u32>(
        &self,
        ray: &Ray<T>,
        hit: &Hit<T>,
        depth: u32,
        weight: T,
        limits: &TraceLimits<T>,
        counts: &mut RayCounts,
    ) -> [Option<Secondary<T>>; 2] {
        let mut spawned = [None, None];
        if !has(FX, REFLECTION | REFRACTION) || depth >= limits.max_depth {
            return spawned;
        }
        let (m, d, p, ar) = (self.m, &ray.dir, &hit.point, &limits.arith);
        let (ng, ns) = (&self.ng, &self.ns);
        let mut kr = m.ks;
        if has(FX, REFRACTION) && m.kt > T::ZERO {
            let eta = if self.entering { m.ior.recip() } else { m.ior };
            match d.refract(ns, eta) {
                Some(t_dir) if wanted::<T, FX>(weight * m.kt, limits) => {
                    counts.refraction += 1;
                    let t_dir = ar.normalize(&t_dir);
                    spawned[0] = Some(Secondary {
                        ray: Ray::new(offset_ray_from(p, ng, &self.above, &t_dir), t_dir),
                        weight: weight * m.kt,
                        k: m.kt,
                        filter: Some(m.color),
                    });
                }
                Some(_) => {}
                None => kr += m.kt,
            }
        }
        let spawn_reflection = kr > T::ZERO || (limits.spd && m.kt > T::ZERO);
        if has(FX, REFLECTION) && spawn_reflection && wanted::<T, FX>(weight * kr, limits) {
            counts.reflection += 1;
            let r_dir = ar.normalize(&ar.reflect(d, ns));
            spawned[1] = Some(Secondary {
                ray: Ray::new(offset_ray_from(p, ng, &self.above, &r_dir), r_dir),
                weight: weight * kr,
                k: kr,
                filter: None,
            });
        }
        spawned
    }
}

/// Lights and ray depths with a shadow cache entry; shadow rays of others go uncached
/// (the shadow packets' cache of [`crate::packets`] keeps as many lights).
pub(crate) const CACHE_LIGHTS: usize = 8;
/// See [`CACHE_LIGHTS`].
const CACHE_DEPTHS: usize = 8;

thread_local! {
    /// The last occluder found per ray depth and light on this thread (Haines and
    /// Greenberg 1986), tested before the BVH walk. It only decides how soon an
    /// occluder is found, never whether one is, so images do not depend on which
    /// thread shaded which pixel before.
    static SHADOW_CACHE: [[Cell<u32>; CACHE_LIGHTS]; CACHE_DEPTHS] =
        const { [const { [const { Cell::new(NO_HINT) }; CACHE_LIGHTS] }; CACHE_DEPTHS] };
}

/// Is the shadow ray toward light `light` from a hit of a depth-`depth` ray blocked?
#[inline(always)]
fn occluded_cached<T: Float, const FX: u32>(
    scene: &Scene<T>,
    shadow: &Ray<T>,
    depth: u32,
    light: usize,
) -> bool {
    let level = depth.saturating_sub(1) as usize;
    if level >= CACHE_DEPTHS || light >= CACHE_LIGHTS {
        return scene.geometry.occluded_kinds::<FX>(shadow);
    }
    // The query runs outside `with`, whose closure the optimiser treats less well.
    let mut hint = SHADOW_CACHE.with(|cache| cache[level][light].get());
    let was = hint;
    let blocked = scene.geometry.occluded_hint_kinds::<FX>(shadow, &mut hint);
    if hint != was {
        SHADOW_CACHE.with(|cache| cache[level][light].set(hint));
    }
    blocked
}

/// Is a secondary ray of accumulated weight `w` worth tracing? Always, without adaptive
/// termination in `FX`.
#[inline]
fn wanted<T: Real, const FX: u32>(w: T, limits: &TraceLimits<T>) -> bool {
    !has(FX, ADAPTIVE) || limits.threshold <= T::ZERO || w >= limits.threshold
}
