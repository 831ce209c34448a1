//! The effect set: which parts of the Whitted model and which primitive kinds a render
//! needs, derived once from the scene and the settings, and the table of renderers
//! specialised for the effect sets that occur.
//!
//! An effect set is a bit mask ([`EffectSet::bits`]). The shading, rendering and
//! intersection code take it as a `const FX: u32` generic parameter, so a renderer
//! compiled for a set without, say, refraction contains no refraction code and no branch
//! that asks for it; the per-material and per-light tests that remain (`Ks > 0`, a light
//! facing the surface, an adaptive weight) only decide whether a ray is worth tracing.
//!
//! # Instantiations
//! An `f32` renderer exists for each entry of [`INSTANCES`]: the effect sets the Standard
//! Procedural Databases need with the default settings, plus the general one ([`ALL`]);
//! `f64` has the general one only (see [`crate::render::specialised`]). At run time
//! [`choose`] takes the cheapest entry that contains every effect the scene needs,
//! falling back to the general renderer, so any scene renders with some entry and the
//! number of compiled renderers stays fixed whatever the scene.
//! Every entry is a superset of what it is chosen for, and an effect a renderer keeps
//! but the scene lacks has no effect on the image: the specialised and the general
//! renderer give the same image bit for bit and trace the same rays.

use crate::geometry::kinds;
use crate::render::Settings;
use crate::world::Scene;
use serde::Serialize;
use vecexpr::{Expr, Real};

/// Shadow rays toward point lights (some light has a non-zero intensity).
pub const SHADOWS: u32 = 1 << 8;
/// Phong highlights (some material has `Ks > 0` and there are lights).
pub const SPECULAR: u32 = 1 << 9;
/// Mirror reflection rays (some material reflects, or transmits, which may reflect
/// totally, and the depth allows secondary rays).
pub const REFLECTION: u32 = 1 << 10;
/// Refraction rays (some material has `T > 0` and the depth allows secondary rays).
pub const REFRACTION: u32 = 1 << 11;
/// More than one eye ray per pixel (`--aa` above 1).
pub const SUPERSAMPLING: u32 = 1 << 12;
/// Adaptive termination: secondary rays below a weight threshold are not traced.
pub const ADAPTIVE: u32 = 1 << 13;
/// Spheres in the scene.
pub const SPHERES: u32 = kinds::SPHERES;
/// Triangles in the scene (polygons, patches and meshes).
pub const TRIANGLES: u32 = kinds::TRIANGLES;
/// Cones and cylinders in the scene.
pub const CONES: u32 = kinds::CONES;
/// Infinite planes in the scene.
pub const PLANES: u32 = kinds::PLANES;
/// Every effect and every primitive kind: the general renderer.
pub const ALL: u32 =
    SHADOWS | SPECULAR | REFLECTION | REFRACTION | SUPERSAMPLING | ADAPTIVE | kinds::ALL;

/// Names of the bits, in the order [`EffectSet::names`] lists them.
pub const NAMES: [(u32, &str); 10] = [
    (SHADOWS, "shadows"),
    (SPECULAR, "specular"),
    (REFLECTION, "reflection"),
    (REFRACTION, "refraction"),
    (SUPERSAMPLING, "supersampling"),
    (ADAPTIVE, "adaptive"),
    (SPHERES, "spheres"),
    (TRIANGLES, "triangles"),
    (CONES, "cones"),
    (PLANES, "planes"),
];

/// Is `bit` in the effect set `fx`? (A `const fn`, so in code generic over `FX` the
/// test folds to a constant.)
#[inline(always)]
pub const fn has(fx: u32, bit: u32) -> bool {
    fx & bit != 0
}

/// How the renderer is chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
#[serde(rename_all = "lowercase")]
pub enum EffectsMode {
    /// The specialised renderer for the effects the scene and settings need.
    #[default]
    Auto,
    /// The general renderer, with every effect compiled in.
    All,
}

impl EffectsMode {
    /// `"auto"` or `"all"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Auto => "auto",
            Self::All => "all",
        }
    }
}

/// A set of effects and primitive kinds, as a bit mask of the constants in this module.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct EffectSet(u32);

impl EffectSet {
    /// The general set: everything.
    pub const ALL: Self = Self(ALL);

    /// From a bit mask (bits outside [`ALL`] are dropped).
    pub const fn from_bits(bits: u32) -> Self {
        Self(bits & ALL)
    }

    /// The bit mask.
    pub const fn bits(self) -> u32 {
        self.0
    }

    /// Does this set contain every effect of `other`?
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// The effects `scene` needs when rendered with `settings`.
    ///
    /// The tests mirror the shading code's own: a light counts if its intensity is not
    /// `<= 0` in every channel, a highlight needs `Ks > 0` and a light, a reflection ray
    /// needs `Ks > 0` or `T > 0` (SPD's rule and total internal reflection) and depth
    /// above 1, a refraction ray `T > 0` and depth above 1, adaptive termination a
    /// threshold not `<= 0`.
    pub fn required<T: Real>(scene: &Scene<T>, settings: &Settings) -> Self {
        let limits = settings.limits::<T>();
        let lit = scene
            .lights
            .iter()
            .any(|l| not_at_most_zero(l.intensity.max_element()));
        let any = |f: fn(&crate::Material<T>) -> bool| scene.materials.iter().any(f);
        let specular = any(|m| m.ks > T::ZERO);
        let transmits = any(|m| m.kt > T::ZERO);
        let secondary = limits.max_depth > 1;
        let mut bits = scene.geometry.kinds();
        let mut set = |on: bool, bit: u32| {
            if on {
                bits |= bit;
            }
        };
        set(lit, SHADOWS);
        set(lit && specular, SPECULAR);
        set(secondary && (specular || transmits), REFLECTION);
        set(secondary && transmits, REFRACTION);
        set(!settings.spd && settings.aa > 1, SUPERSAMPLING);
        set(
            secondary && (specular || transmits) && not_at_most_zero(limits.threshold),
            ADAPTIVE,
        );
        Self(bits)
    }

    /// The names of the effects in the set, in [`NAMES`] order.
    pub fn names(self) -> Vec<&'static str> {
        NAMES
            .iter()
            .filter(|(b, _)| has(self.0, *b))
            .map(|(_, n)| *n)
            .collect()
    }

    /// Is this the general set?
    pub fn is_general(self) -> bool {
        self.0 == ALL
    }
}

/// `!(x <= 0)`: positive or NaN, the cases in which the shading code's `x <= 0` tests
/// do not skip.
fn not_at_most_zero<T: Real>(x: T) -> bool {
    x.is_nan() || x > T::ZERO
}

impl Serialize for EffectSet {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        self.names().serialize(s)
    }
}

/// The effect set chosen for a render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct EffectChoice {
    /// `auto` or `all`.
    pub mode: EffectsMode,
    /// What the scene and settings need.
    pub required: EffectSet,
    /// What the renderer that ran was compiled for (a superset of `required`).
    pub renderer: EffectSet,
    /// Was it the general renderer?
    pub general: bool,
}

impl EffectChoice {
    /// The renderer for `required` under `mode`.
    pub fn new(mode: EffectsMode, required: EffectSet) -> Self {
        let renderer = match mode {
            EffectsMode::Auto => choose(required),
            EffectsMode::All => EffectSet::ALL,
        };
        Self {
            mode,
            required,
            renderer,
            general: renderer.is_general(),
        }
    }
}

/// Declares the specialised effect sets: [`INSTANCES`] and the dispatch from a set in it
/// to the renderer monomorphised for it.
macro_rules! effect_table {
    ($($(#[$doc:meta])* $name:ident = $bits:expr;)*) => {
        $($(#[$doc])* pub const $name: u32 = $bits;)*

        /// Every effect set with its own renderer, the general one ([`ALL`]) last.
        pub const INSTANCES: &[u32] = &[$($name,)* ALL];

        /// Calls `f` monomorphised for `set`, which must be in [`INSTANCES`] (anything
        /// else runs the general instance).
        #[inline]
        pub(crate) fn dispatch<R, F: EffectFn<R>>(set: EffectSet, f: F) -> R {
            match set.bits() {
                $($name => f.call::<{ $name }>(),)*
                _ => f.call::<ALL>(),
            }
        }
    };
}

/// Code generic over an effect set, called through [`dispatch`].
pub(crate) trait EffectFn<R> {
    /// Runs the instance for `FX`.
    fn call<const FX: u32>(self) -> R;
}

effect_table! {
    /// Matte triangles: tetra, sombrero, nurbtst.
    MATTE_TRIANGLES = SHADOWS | TRIANGLES;
    /// Matte spheres, triangles and cones: tree.
    MATTE_MIXED = SHADOWS | SPHERES | TRIANGLES | CONES;
    /// Mirrors of triangles: teapot.
    MIRROR_TRIANGLES = SHADOWS | SPECULAR | REFLECTION | TRIANGLES;
    /// Mirrors of spheres: shells.
    MIRROR_SPHERES = SHADOWS | SPECULAR | REFLECTION | SPHERES;
    /// Mirrors of spheres and triangles: balls.
    MIRROR_SPHERES_TRIANGLES = SHADOWS | SPECULAR | REFLECTION | SPHERES | TRIANGLES;
    /// Mirrors of spheres and cones: jacks, lattice.
    MIRROR_SPHERES_CONES = SHADOWS | SPECULAR | REFLECTION | SPHERES | CONES;
    /// Mirrors of every bounded kind: rings.
    MIRROR_MIXED = SHADOWS | SPECULAR | REFLECTION | SPHERES | TRIANGLES | CONES;
    /// Glass and mirrors of spheres and triangles: mount.
    GLASS_SPHERES_TRIANGLES = SHADOWS | SPECULAR | REFLECTION | REFRACTION | SPHERES | TRIANGLES;
}

/// The cheapest entry of [`INSTANCES`] that contains `required`: the one with the fewest
/// effects, the earliest on a tie; the general set if none does.
pub fn choose(required: EffectSet) -> EffectSet {
    INSTANCES
        .iter()
        .map(|&b| EffectSet(b))
        .filter(|s| s.contains(required))
        .min_by_key(|s| s.0.count_ones())
        .unwrap_or(EffectSet::ALL)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn instances_are_distinct_and_end_with_the_general_set() {
        assert_eq!(INSTANCES.last(), Some(&ALL));
        for (i, a) in INSTANCES.iter().enumerate() {
            assert_eq!(a & !ALL, 0);
            assert!(INSTANCES[i + 1..].iter().all(|b| a != b));
        }
    }

    #[test]
    fn choice_is_a_superset() {
        for bits in [
            0,
            SHADOWS,
            SHADOWS | TRIANGLES,
            SHADOWS | PLANES,
            ALL,
            SUPERSAMPLING,
        ] {
            let need = EffectSet::from_bits(bits);
            assert!(choose(need).contains(need));
        }
        assert_eq!(
            choose(EffectSet::from_bits(TRIANGLES)).bits(),
            MATTE_TRIANGLES
        );
        assert_eq!(
            choose(EffectSet::from_bits(SHADOWS | PLANES)),
            EffectSet::ALL
        );
    }

    #[test]
    fn names_follow_the_bits() {
        let s = EffectSet::from_bits(SHADOWS | TRIANGLES);
        assert_eq!(s.names(), ["shadows", "triangles"]);
        assert_eq!(EffectSet::ALL.names().len(), NAMES.len());
    }
}
