//! The ray-tracing kernels on 3-vectors: normalize, cross, reflect, refract, and
//! reflect followed by normalize (the secondary-ray step), for one vector, a batch of
//! 4096 in AoS form and the same batch as SoA packets (plain arrays, ultraviolet, and
//! vecexpr's explicit SIMD lanes).

use crate::{Batch, P16, P8};
use benches::config::{self, AOS, SOA16, SOA8};
use benches::data::Pcg32;
use benches::hand;
use benches::run::{batch, lanes, load3, single, soa, store3};
use criterion::{Criterion, Throughput};
use ultraviolet::f32x8;
use vecexpr::simd::{Isa, Kernel, SimdF32};
use vecexpr::{Expr, Scalar};

/// Index of refraction ratio used by `refract` (air to glass).
const ETA: f32 = 1.0 / 1.5;

/// Unit incident directions and unit normals facing them, as every representation.
fn rays(seed: u64) -> (Batch, Batch) {
    let mut rng = Pcg32::new(seed);
    let n = rng.units(config::BATCH);
    // Incident directions against the normal (N·I < 0), as a tracer produces them.
    let i: Vec<[f32; 3]> = n
        .iter()
        .map(|&nv| {
            let mut d = rng.unit3();
            if hand::dot3(d, nv) > 0.0 {
                d = d.map(|x| -x);
            }
            d
        })
        .collect();
    (Batch::new(i), Batch::new(n))
}

macro_rules! geometry_group {
    ($fn_name:ident, $group:literal, $seed:literal,
     vecexpr: |$va:ident, $vb:ident| $vx:expr,
     eager: |$ea:ident, $eb:ident| $eg:expr,
     hand: |$ha:ident, $hb:ident| $hd:expr,
     glam: |$ga:ident, $gb:ident| $gl:expr,
     nalgebra: |$na:ident, $nb:ident| $ne:expr,
     ultraviolet: |$ua:ident, $ub:ident| $uv:expr
     $(, vec3a: |$xa:ident, $xb:ident| $xe:expr)?
     $(, vec3a_fast: |$fa:ident, $fb:ident| $fe:expr)? $(,)?) => {
        #[doc = concat!("The criterion group `", $group, "`.")]
        pub fn $fn_name(c: &mut Criterion) {
            use benches::eager::Eager;
            use glam::{Vec3, Vec3A};
            use nalgebra::Vector3;
            use ultraviolet::Vec3x8;
            use vecexpr::{typenum::U3, Vector};
            let mut g = config::group(c, $group);
            let (i, n) = rays($seed);
            let hand = |$ha: [f32; 3], $hb: [f32; 3]| -> [f32; 3] { $hd };
            single(
                &mut g,
                "vecexpr",
                "3",
                i.vx[0],
                n.vx[0],
                |$va: &Vector<f32, U3>, $vb| $vx,
            );
            single(
                &mut g,
                "eager",
                "3",
                i.eager[0],
                n.eager[0],
                |$ea: &Eager<f32, U3>, $eb| $eg,
            );
            single(&mut g, "hand", "3", i.arr[0], n.arr[0], |a, b| hand(*a, *b));
            single(
                &mut g,
                "glam_vec3",
                "3",
                i.glam3[0],
                n.glam3[0],
                |$ga: &Vec3, $gb: &Vec3| {
                    let ($ga, $gb) = (*$ga, *$gb);
                    $gl
                },
            );
            single(
                &mut g,
                "glam_vec3a",
                "3",
                i.glam3a[0],
                n.glam3a[0],
                |$ga: &Vec3A, $gb: &Vec3A| {
                    let ($ga, $gb) = (*$ga, *$gb);
                    $gl
                },
            );
            $(single(
                &mut g,
                "vecexpr_vec3a",
                "3",
                i.v3a[0],
                n.v3a[0],
                |$xa: &vecexpr::Vec3A, $xb: &vecexpr::Vec3A| {
                    let ($xa, $xb) = (*$xa, *$xb);
                    $xe
                },
            );)?
            $(single(
                &mut g,
                "vecexpr_vec3a_fast",
                "3",
                i.v3a[0],
                n.v3a[0],
                |$fa: &vecexpr::Vec3A, $fb: &vecexpr::Vec3A| {
                    let ($fa, $fb) = (*$fa, *$fb);
                    $fe
                },
            );)?
            single(
                &mut g,
                "nalgebra",
                "3",
                i.na[0],
                n.na[0],
                |$na: &Vector3<f32>, $nb: &Vector3<f32>| $ne,
            );
            g.throughput(Throughput::Elements(config::BATCH as u64));
            batch(
                &mut g,
                "vecexpr",
                AOS,
                &i.vx,
                &n.vx,
                |$va: &Vector<f32, U3>, $vb| $vx,
            );
            batch(
                &mut g,
                "eager",
                AOS,
                &i.eager,
                &n.eager,
                |$ea: &Eager<f32, U3>, $eb| $eg,
            );
            batch(&mut g, "hand", AOS, &i.arr, &n.arr, |a, b| hand(*a, *b));
            batch(
                &mut g,
                "glam_vec3",
                AOS,
                &i.glam3,
                &n.glam3,
                |$ga: &Vec3, $gb: &Vec3| {
                    let ($ga, $gb) = (*$ga, *$gb);
                    $gl
                },
            );
            batch(
                &mut g,
                "glam_vec3a",
                AOS,
                &i.glam3a,
                &n.glam3a,
                |$ga: &Vec3A, $gb: &Vec3A| {
                    let ($ga, $gb) = (*$ga, *$gb);
                    $gl
                },
            );
            $(batch(
                &mut g,
                "vecexpr_vec3a",
                AOS,
                &i.v3a,
                &n.v3a,
                |$xa: &vecexpr::Vec3A, $xb: &vecexpr::Vec3A| {
                    let ($xa, $xb) = (*$xa, *$xb);
                    $xe
                },
            );)?
            $(batch(
                &mut g,
                "vecexpr_vec3a_fast",
                AOS,
                &i.v3a,
                &n.v3a,
                |$fa: &vecexpr::Vec3A, $fb: &vecexpr::Vec3A| {
                    let ($fa, $fb) = (*$fa, *$fb);
                    $fe
                },
            );)?
            batch(
                &mut g,
                "nalgebra",
                AOS,
                &i.na,
                &n.na,
                |$na: &Vector3<f32>, $nb: &Vector3<f32>| $ne,
            );
            batch(
                &mut g,
                "vecexpr",
                SOA8,
                &i.p8,
                &n.p8,
                |$va: &Vector<P8, U3>, $vb| $vx,
            );
            batch(
                &mut g,
                "eager",
                SOA8,
                &i.e8,
                &n.e8,
                |$ea: &Eager<P8, U3>, $eb| $eg,
            );
            soa(&mut g, "hand", SOA8, &i.soa, &n.soa, hand);
            batch(
                &mut g,
                "ultraviolet",
                SOA8,
                &i.uv,
                &n.uv,
                |$ua: &Vec3x8, $ub: &Vec3x8| {
                    let ($ua, $ub) = (*$ua, *$ub);
                    $uv
                },
            );
            batch(
                &mut g,
                "vecexpr",
                SOA16,
                &i.p16,
                &n.p16,
                |$va: &Vector<P16, U3>, $vb| $vx,
            );
            // The same expression on explicit lanes: the loop over all packets is one
            // kernel, compiled for AVX2 (`F32x8`) or AVX-512 (`F32x16`) by `dispatch`.
            struct Lanes<'a> {
                a: &'a [f32],
                b: &'a [f32],
                out: &'a mut [f32],
            }
            impl Kernel for Lanes<'_> {
                type Output = ();
                #[inline(always)]
                fn run<S: SimdF32>(self) {
                    let w = 3 * S::LANES;
                    let packets = self
                        .out
                        .chunks_exact_mut(w)
                        .zip(self.a.chunks_exact(w).zip(self.b.chunks_exact(w)));
                    for (o, (x, y)) in packets {
                        let ($va, $vb) = (&load3::<S>(x), &load3::<S>(y));
                        let r: Vector<S, U3> = $vx;
                        store3(r, o);
                    }
                }
            }
            let run =
                |isa: Isa, a: &[f32], b: &[f32], out: &mut [f32]| isa.dispatch(Lanes { a, b, out });
            lanes(
                &mut g,
                "vecexpr_f32x8",
                SOA8,
                Isa::Avx2,
                &i.lanes8,
                &n.lanes8,
                run,
            );
            lanes(
                &mut g,
                "vecexpr_f32x16",
                SOA16,
                Isa::Avx512,
                &i.lanes16,
                &n.lanes16,
                run,
            );
            g.finish();
        }
    };
}

geometry_group!(normalize, "normalize", 4,
    vecexpr: |a, _b| a.normalize(),
    eager: |a, _b| a.normalize(),
    hand: |a, _b| hand::normalize3(a),
    glam: |a, _b| a.normalize(),
    nalgebra: |a, _b| a.normalize(),
    ultraviolet: |a, _b| a.normalized(),
    vec3a: |a, _b| a.normalize(),
    vec3a_fast: |a, _b| a.normalize_fast(),
);

geometry_group!(cross, "cross", 5,
    vecexpr: |a, b| a.cross(b),
    eager: |a, b| a.cross(b),
    hand: |a, b| hand::cross3(a, b),
    glam: |a, b| a.cross(b),
    nalgebra: |a, b| a.cross(b),
    ultraviolet: |a, b| a.cross(b),
    vec3a: |a, b| a.cross(b),
);

geometry_group!(reflect, "reflect", 6,
    vecexpr: |a, b| a.reflect(b),
    eager: |a, b| a.reflect(b),
    hand: |a, b| hand::reflect3(a, b),
    glam: |a, b| a.reflect(b),
    nalgebra: |a, b| a - b * (2.0 * b.dot(a)),
    ultraviolet: |a, b| a.reflected(b),
    vec3a: |a, b| a.reflect(b),
);

geometry_group!(refract, "refract", 7,
    vecexpr: |a, b| a.refract_masked(b, Scalar::splat(ETA)).0,
    eager: |a, b| a.refract(b, Scalar::splat(ETA)),
    hand: |a, b| hand::refract3(a, b, ETA),
    glam: |a, b| a.refract(b, ETA),
    nalgebra: |a, b| {
        // nalgebra has no refract: the formula, as the others compute it.
        let ni = b.dot(a);
        let k = 1.0 - ETA * ETA * (1.0 - ni * ni);
        let (s, t) = if k >= 0.0 { (ETA, ETA * ni + k.sqrt()) } else { (0.0, 0.0) };
        a * s - b * t
    },
    ultraviolet: |a, b| a.refracted(b, f32x8::splat(ETA)),
);

geometry_group!(reflect_normalize, "reflect_normalize", 8,
    vecexpr: |a, b| a.reflect(b).normalize(),
    eager: |a, b| a.reflect(b).normalize(),
    hand: |a, b| hand::normalize3(hand::reflect3(a, b)),
    glam: |a, b| a.reflect(b).normalize(),
    nalgebra: |a, b| (a - b * (2.0 * b.dot(a))).normalize(),
    ultraviolet: |a, b| a.reflected(b).normalized(),
    vec3a: |a, b| a.reflect(b).normalize(),
    vec3a_fast: |a, b| a.reflect(b).normalize_fast(),
);

/// The criterion group `normalize_zero_lane`: `normalize` on SoA packets each of which
/// holds one zero vector (lane 3 of every 8), so vecexpr's robust normalize takes its
/// rescaling path in every packet. (ultraviolet's unchecked `normalized` gives NaN in
/// those lanes; it is here for scale.)
pub fn normalize_zero_lane(c: &mut Criterion) {
    use ultraviolet::Vec3x8;
    use vecexpr::{typenum::U3, Vector};
    let mut g = config::group(c, "normalize_zero_lane");
    let mut v = Pcg32::new(9).units(config::BATCH);
    for p in v.chunks_exact_mut(8) {
        p[3] = [0.0; 3];
    }
    let v = Batch::new(v);
    g.throughput(Throughput::Elements(config::BATCH as u64));
    batch(
        &mut g,
        "vecexpr",
        SOA8,
        &v.p8,
        &v.p8,
        |a: &Vector<P8, U3>, _| a.normalize(),
    );
    batch(
        &mut g,
        "ultraviolet",
        SOA8,
        &v.uv,
        &v.uv,
        |a: &Vec3x8, _| a.normalized(),
    );
    batch(
        &mut g,
        "vecexpr",
        SOA16,
        &v.p16,
        &v.p16,
        |a: &Vector<P16, U3>, _| a.normalize(),
    );
    struct Lanes<'a> {
        a: &'a [f32],
        out: &'a mut [f32],
    }
    impl Kernel for Lanes<'_> {
        type Output = ();
        #[inline(always)]
        fn run<S: SimdF32>(self) {
            let w = 3 * S::LANES;
            for (o, x) in self.out.chunks_exact_mut(w).zip(self.a.chunks_exact(w)) {
                store3(load3::<S>(x).normalize(), o);
            }
        }
    }
    let run = |isa: Isa, a: &[f32], _: &[f32], out: &mut [f32]| isa.dispatch(Lanes { a, out });
    lanes(
        &mut g,
        "vecexpr_f32x8",
        SOA8,
        Isa::Avx2,
        &v.lanes8,
        &v.lanes8,
        run,
    );
    lanes(
        &mut g,
        "vecexpr_f32x16",
        SOA16,
        Isa::Avx512,
        &v.lanes16,
        &v.lanes16,
        run,
    );
    g.finish();
}
