//! Spheres as Embree 3 user geometry: the ray/sphere test and the bodies of the intersect
//! and occluded callbacks of the Embree bench (`benches/embree/main.rs`, configuration
//! "Embree user spheres").
//!
//! Kept here, in plain Rust over slices, so that the lane handling and the sphere test
//! are unit-tested without linking Embree (`cargo test -p benches --lib user_spheres`);
//! the bench's `extern "C"` callbacks only turn Embree's argument structures into these
//! slices.
//!
//! **The test.** E. Haines, J. Günther, T. Akenine-Möller, "Precision Improvements for
//! Ray/Sphere Intersection", *Ray Tracing Gems* (2019), chapter 7. With $f = o - c$ the
//! quadratic is $a t^2 + 2 b t + c' = 0$, $a = d \cdot d$, $b = f \cdot d$,
//! $c' = f \cdot f - r^2$. The discriminant $b^2 - a c'$ is computed as
//! $a (r^2 - |f - (b / a) d|^2)$, through the squared distance from the centre to the
//! ray's line, which does not cancel when the sphere is small against its distance; the
//! roots are $q / a$ and $c' / q$ with $q = -(b + \mathrm{sign}(b) \sqrt{\cdot})$, so no
//! two nearly equal numbers are subtracted. The tracer's own sphere test
//! (`tracer/src/geometry/sphere.rs`) follows the same chapter; this one is written
//! separately on purpose: the comparison is of Embree calling back into a plain
//! sphere test of its user's, not of Embree calling the tracer.
//!
//! **The layouts.** Embree hands a callback `N` rays (1 for `rtcIntersect1`, its
//! packet width or 16 for `rtcIntersect16`) in structure-of-arrays form
//! (`embree3/rtcore_ray.h`, `RTCRayN_*` and `RTCHitN_*`): field `k` of ray `i` is the
//! 32-bit word `k * N + i`, the twelve ray fields first ([`RAY_FIELDS`]), then, for the
//! closest-hit query, the eight hit fields ([`HIT_FIELDS`]). With `N = 1` this is the
//! layout of `RTCRayHit`. Every `N` is handled the same way, lane by lane, skipping the
//! lanes whose `valid` entry is 0.
//!
//! **What a hit writes** (Embree's `rtcSetGeometryIntersectFunction` contract): only
//! for a distance strictly inside `(tnear, tfar)`, the new `tfar`, the outward geometric
//! normal $f + t d$ (not normalised, as Embree's own are not), `u = v = 0` (no surface
//! parametrisation is needed here), the primitive, geometry and current instance ids.
//! A miss leaves the lane untouched. The occluded callback sets `tfar` to $-\infty$ for
//! a blocked lane. Neither calls `rtcFilterIntersection`: the bench's scenes and contexts
//! have no filter functions.

/// Number of 32-bit fields of a ray (`RTCRayN`): origin, tnear, direction, time, tfar,
/// mask, id, flags.
pub const RAY_FIELDS: usize = 12;
/// Number of 32-bit fields of a hit (`RTCHitN`) with `RTC_MAX_INSTANCE_LEVEL_COUNT` 1:
/// normal, u, v, primID, geomID, one instID.
pub const HIT_FIELDS: usize = 8;

/// Ray field `org_x` (then `org_y`, `org_z`).
pub const ORG: usize = 0;
/// Ray field `tnear`.
pub const TNEAR: usize = 3;
/// Ray field `dir_x` (then `dir_y`, `dir_z`).
pub const DIR: usize = 4;
/// Ray field `tfar`.
pub const TFAR: usize = 8;
/// Hit field `Ng_x` (then `Ng_y`, `Ng_z`), counted from the start of the hit.
pub const NG: usize = 0;
/// Hit field `u`.
pub const U: usize = 3;
/// Hit field `v`.
pub const V: usize = 4;
/// Hit field `primID`.
pub const PRIM_ID: usize = 5;
/// Hit field `geomID`.
pub const GEOM_ID: usize = 6;
/// Hit field `instID[0]`.
pub const INST_ID: usize = 7;

#[inline(always)]
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The nearest distance `t` strictly inside `(tnear, tfar)` where the ray
/// `origin + t dir` meets the sphere `s` (centre x, y, z and radius), with the precision
/// measures of Haines et al. (module docs). A ray that starts inside finds the far wall.
#[inline(always)]
pub fn sphere_hit(
    s: [f32; 4],
    origin: [f32; 3],
    dir: [f32; 3],
    tnear: f32,
    tfar: f32,
) -> Option<f32> {
    let f = [origin[0] - s[0], origin[1] - s[1], origin[2] - s[2]];
    let a = dot(dir, dir);
    let b = dot(f, dir);
    let r2 = s[3] * s[3];
    // The ray's closest approach to the centre: |l| is the centre's distance to the line.
    let k = b / a;
    let l = [f[0] - k * dir[0], f[1] - k * dir[1], f[2] - k * dir[2]];
    let disc = a * (r2 - dot(l, l));
    // A NaN (a zero direction) goes on to NaN distances, which the interval rejects.
    if disc < 0.0 {
        return None;
    }
    let c = dot(f, f) - r2;
    let q = -(b + disc.sqrt().copysign(b));
    let (t0, t1) = (c / q, q / a);
    let (near, far) = if t1 < t0 { (t1, t0) } else { (t0, t1) };
    let inside = |t: f32| t > tnear && t < tfar;
    if inside(near) {
        Some(near)
    } else if inside(far) {
        Some(far)
    } else {
        None
    }
}

/// One lane's ray, read from a packet of `n` rays in `words` (layout in the module docs).
#[inline(always)]
fn lane_ray(words: &[u32], n: usize, i: usize) -> ([f32; 3], [f32; 3], f32, f32) {
    let f = |k: usize| f32::from_bits(words[k * n + i]);
    (
        [f(ORG), f(ORG + 1), f(ORG + 2)],
        [f(DIR), f(DIR + 1), f(DIR + 2)],
        f(TNEAR),
        f(TFAR),
    )
}

/// The closest-hit callback's work: every valid lane of the `n = valid.len()` rays and
/// hits in `rayhit` (`(RAY_FIELDS + HIT_FIELDS) * n` words) against the sphere `s`,
/// which is primitive `prim_id` of geometry `geom_id`; a hit records `inst_id` (the
/// context's current instance) as the instance id.
///
/// # Panics
/// If `rayhit` is shorter than `(RAY_FIELDS + HIT_FIELDS) * n` words.
#[inline(always)]
pub fn intersect_lanes(
    valid: &[i32],
    s: [f32; 4],
    prim_id: u32,
    geom_id: u32,
    inst_id: u32,
    rayhit: &mut [u32],
) {
    let n = valid.len();
    let (ray, hit) = rayhit[..(RAY_FIELDS + HIT_FIELDS) * n].split_at_mut(RAY_FIELDS * n);
    for (i, _) in valid.iter().enumerate().filter(|(_, v)| **v != 0) {
        let (o, d, tnear, tfar) = lane_ray(ray, n, i);
        let Some(t) = sphere_hit(s, o, d, tnear, tfar) else {
            continue;
        };
        ray[TFAR * n + i] = t.to_bits();
        for a in 0..3 {
            // The outward normal o + t d - centre = f + t d.
            hit[(NG + a) * n + i] = (o[a] - s[a] + t * d[a]).to_bits();
        }
        hit[U * n + i] = 0f32.to_bits();
        hit[V * n + i] = 0f32.to_bits();
        hit[PRIM_ID * n + i] = prim_id;
        hit[GEOM_ID * n + i] = geom_id;
        hit[INST_ID * n + i] = inst_id;
    }
}

/// The occluded callback's work: every valid lane of the `n = valid.len()` rays in `ray`
/// (`RAY_FIELDS * n` words) that meets the sphere `s` inside `(tnear, tfar)` gets
/// `tfar = -inf`.
///
/// # Panics
/// If `ray` is shorter than `RAY_FIELDS * n` words.
#[inline(always)]
pub fn occluded_lanes(valid: &[i32], s: [f32; 4], ray: &mut [u32]) {
    let n = valid.len();
    let ray = &mut ray[..RAY_FIELDS * n];
    for (i, _) in valid.iter().enumerate().filter(|(_, v)| **v != 0) {
        let (o, d, tnear, tfar) = lane_ray(ray, n, i);
        if sphere_hit(s, o, d, tnear, tfar).is_some() {
            ray[TFAR * n + i] = f32::NEG_INFINITY.to_bits();
        }
    }
}

/// The bounding box of the sphere `s`: lower and upper corners.
#[inline]
pub fn sphere_bounds(s: [f32; 4]) -> ([f32; 3], [f32; 3]) {
    (
        [s[0] - s[3], s[1] - s[3], s[2] - s[3]],
        [s[0] + s[3], s[1] + s[3], s[2] + s[3]],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit sphere at (0, 0, 5).
    const S: [f32; 4] = [0.0, 0.0, 5.0, 1.0];

    #[test]
    fn front_wall_then_far_wall_from_inside() {
        let t = sphere_hit(S, [0.0; 3], [0.0, 0.0, 1.0], 0.0, f32::INFINITY);
        assert_eq!(t, Some(4.0));
        // From the centre, the far wall at distance 1.
        let t = sphere_hit(S, [0.0, 0.0, 5.0], [0.0, 0.0, 1.0], 0.0, f32::INFINITY);
        assert_eq!(t, Some(1.0));
        // A direction of length 2 halves the distances.
        let t = sphere_hit(S, [0.0; 3], [0.0, 0.0, 2.0], 0.0, f32::INFINITY);
        assert_eq!(t, Some(2.0));
    }

    #[test]
    fn interval_is_open_at_both_ends() {
        let d = [0.0, 0.0, 1.0];
        // tfar at the front wall: no hit (the interval is open), tfar past it: hit.
        assert_eq!(sphere_hit(S, [0.0; 3], d, 0.0, 4.0), None);
        assert_eq!(sphere_hit(S, [0.0; 3], d, 0.0, 4.5), Some(4.0));
        // tnear at the front wall: the far wall.
        assert_eq!(sphere_hit(S, [0.0; 3], d, 4.0, 100.0), Some(6.0));
        assert_eq!(sphere_hit(S, [0.0; 3], d, 6.0, 100.0), None);
        // Behind the origin.
        assert_eq!(sphere_hit(S, [0.0, 0.0, 10.0], d, 0.0, 100.0), None);
    }

    #[test]
    fn misses_beside_and_grazes() {
        let d = [0.0, 0.0, 1.0];
        assert_eq!(sphere_hit(S, [1.5, 0.0, 0.0], d, 0.0, 100.0), None);
        // Just inside the silhouette: a hit near t = 5.
        let t = sphere_hit(S, [0.999, 0.0, 0.0], d, 0.0, 100.0).unwrap();
        assert!(
            (t - (5.0 - (1.0f32 - 0.999 * 0.999).sqrt())).abs() < 1e-4,
            "{t}"
        );
        // A degenerate direction is a miss, not a panic or a NaN hit.
        assert_eq!(sphere_hit(S, [0.0; 3], [0.0; 3], 0.0, 100.0), None);
    }

    /// A small sphere far away: the naive discriminant b^2 - ac cancels in f32, the
    /// chapter's form does not; the distance matches an f64 evaluation.
    #[test]
    fn small_far_sphere_is_accurate() {
        let s = [0.0, 0.0, 1.0e4, 0.01];
        let o = [0.005, 0.0, 0.0];
        let d = [0.0, 0.0, 1.0];
        let t = sphere_hit(s, o, d, 0.0, f32::INFINITY).expect("hits");
        let exact = 1.0e4 - (0.01f64 * 0.01 - 0.005 * 0.005).sqrt();
        assert!((f64::from(t) - exact).abs() < 1e-3, "{t} against {exact}");
        // The naive form loses the hit or its accuracy here.
        let (b, c) = (-1.0e4f32, 1.0e8f32 + 0.005 * 0.005 - 0.01 * 0.01);
        let naive = b * b - c;
        assert!(
            naive <= 0.0,
            "the naive discriminant no longer cancels: {naive}"
        );
    }

    /// A packet of `n` rays in Embree's SoA layout; lane `i` starts at x = `xs[i]`,
    /// along +z, with `tnear` 0 and `tfar` `tfar`.
    fn packet(xs: &[f32], tfar: f32) -> Vec<u32> {
        let n = xs.len();
        let mut w = vec![0xdead_beefu32; (RAY_FIELDS + HIT_FIELDS) * n];
        for (i, &x) in xs.iter().enumerate() {
            let mut set = |k: usize, v: f32| w[k * n + i] = v.to_bits();
            set(ORG, x);
            set(ORG + 1, 0.0);
            set(ORG + 2, 0.0);
            set(TNEAR, 0.0);
            set(DIR, 0.0);
            set(DIR + 1, 0.0);
            set(DIR + 2, 1.0);
            set(TFAR, tfar);
        }
        w
    }

    fn field(w: &[u32], n: usize, k: usize, i: usize) -> f32 {
        f32::from_bits(w[k * n + i])
    }

    #[test]
    fn one_ray_is_rtc_ray_hit() {
        let mut w = packet(&[0.0], 100.0);
        intersect_lanes(&[-1], S, 7, 3, u32::MAX, &mut w);
        assert_eq!(field(&w, 1, TFAR, 0), 4.0);
        let h = RAY_FIELDS;
        assert_eq!(
            [
                field(&w, 1, h + NG, 0),
                field(&w, 1, h + NG + 1, 0),
                field(&w, 1, h + NG + 2, 0)
            ],
            [0.0, 0.0, -1.0]
        );
        assert_eq!((field(&w, 1, h + U, 0), field(&w, 1, h + V, 0)), (0.0, 0.0));
        assert_eq!(
            (w[h + PRIM_ID], w[h + GEOM_ID], w[h + INST_ID]),
            (7, 3, u32::MAX)
        );
    }

    /// Sixteen lanes: hits, misses, invalid lanes and a lane whose tfar is already
    /// nearer; only valid hitting lanes change, each in its own column.
    #[test]
    fn sixteen_lanes_soa() {
        let xs: Vec<f32> = (0..16)
            .map(|i| {
                if i % 3 == 0 {
                    2.0
                } else {
                    0.1 * i as f32 - 0.8
                }
            })
            .collect();
        let n = xs.len();
        let mut w = packet(&xs, 100.0);
        // Lane 7 (valid, its sphere hit near 4) already has a hit at 3.
        w[TFAR * n + 7] = 3.0f32.to_bits();
        let valid: Vec<i32> = (0..16).map(|i| if i % 4 == 1 { 0 } else { -1 }).collect();
        let before = w.clone();
        intersect_lanes(&valid, S, 9, 1, u32::MAX, &mut w);
        for i in 0..n {
            let expect = sphere_hit(
                S,
                [xs[i], 0.0, 0.0],
                [0.0, 0.0, 1.0],
                0.0,
                field(&before, n, TFAR, i),
            );
            let changed = (0..RAY_FIELDS + HIT_FIELDS).any(|k| w[k * n + i] != before[k * n + i]);
            match expect {
                Some(t) if valid[i] != 0 => {
                    assert_eq!(field(&w, n, TFAR, i), t, "lane {i}");
                    assert_eq!(w[(RAY_FIELDS + PRIM_ID) * n + i], 9, "lane {i}");
                    assert_eq!(w[(RAY_FIELDS + GEOM_ID) * n + i], 1, "lane {i}");
                    // The normal points back toward the ray's origin side.
                    assert!(field(&w, n, RAY_FIELDS + NG + 2, i) < 0.0, "lane {i}");
                }
                _ => assert!(!changed, "lane {i} changed"),
            }
        }
        // Some lanes of each sort were exercised.
        assert!(w[(RAY_FIELDS + PRIM_ID) * n + 2] == 9);
        assert!(!(0..n).any(|i| valid[i] == 0 && w[(RAY_FIELDS + PRIM_ID) * n + i] == 9));
        assert_eq!(field(&w, n, TFAR, 7), 3.0);
    }

    #[test]
    fn occluded_sets_minus_infinity() {
        let xs = [0.0, 2.0, 0.5, 0.0];
        let n = xs.len();
        let mut w = packet(&xs, 100.0);
        // Lane 3 stops before the sphere.
        w[TFAR * n + 3] = 3.5f32.to_bits();
        let mut ray = w[..RAY_FIELDS * n].to_vec();
        occluded_lanes(&[-1, -1, 0, -1], S, &mut ray);
        let tfar: Vec<f32> = (0..n).map(|i| field(&ray, n, TFAR, i)).collect();
        assert_eq!(tfar, [f32::NEG_INFINITY, 100.0, 100.0, 3.5]);
    }

    #[test]
    fn bounds_enclose_the_sphere() {
        assert_eq!(sphere_bounds(S), ([-1.0, -1.0, 4.0], [1.0, 1.0, 6.0]));
    }
}
