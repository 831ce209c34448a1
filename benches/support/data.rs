//! Fixed-seed random inputs, so every implementation in a group sees the same numbers
//! on every run.

/// PCG32 (XSH RR 64/32) of O'Neill, "PCG: A Family of Simple Fast Space-Efficient
/// Statistically Good Algorithms for Random Number Generation" (2014): small, fast and
/// reproducible, which is all benchmark data needs.
#[derive(Clone, Debug)]
pub struct Pcg32 {
    state: u64,
    inc: u64,
}

impl Pcg32 {
    /// The generator for `seed` (stream fixed).
    pub fn new(seed: u64) -> Self {
        let mut g = Self {
            state: 0,
            inc: (0xda3e_39cb_94b9_5bdb << 1) | 1,
        };
        g.next_u32();
        g.state = g.state.wrapping_add(seed);
        g.next_u32();
        g
    }

    /// The next 32 random bits.
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Uniform in $[lo, hi)$.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let unit = (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32);
        lo + (hi - lo) * unit
    }

    /// A uniformly random unit 3-vector (normalised Gaussian-free rejection sampling).
    pub fn unit3(&mut self) -> [f32; 3] {
        loop {
            let v = [
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            ];
            let l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
            if l2 > 1e-4 && l2 <= 1.0 {
                let inv = 1.0 / l2.sqrt();
                return v.map(|x| x * inv);
            }
        }
    }

    /// `n` values uniform in $[-1, 1)$.
    pub fn vec(&mut self, n: usize) -> Vec<f32> {
        (0..n).map(|_| self.range(-1.0, 1.0)).collect()
    }

    /// `n` 3-vectors with components uniform in $[-1, 1)$.
    pub fn vec3s(&mut self, n: usize) -> Vec<[f32; 3]> {
        (0..n)
            .map(|_| [0; 3].map(|_| self.range(-1.0, 1.0)))
            .collect()
    }

    /// `n` random unit 3-vectors.
    pub fn units(&mut self, n: usize) -> Vec<[f32; 3]> {
        (0..n).map(|_| self.unit3()).collect()
    }
}

/// A batch of 3-vectors in structure-of-arrays form: all x, then all y, then all z.
#[derive(Clone, Debug, PartialEq)]
pub struct Soa {
    /// x components.
    pub x: Vec<f32>,
    /// y components.
    pub y: Vec<f32>,
    /// z components.
    pub z: Vec<f32>,
}

impl Soa {
    /// The SoA form of `v`.
    pub fn from_aos(v: &[[f32; 3]]) -> Self {
        Self {
            x: v.iter().map(|p| p[0]).collect(),
            y: v.iter().map(|p| p[1]).collect(),
            z: v.iter().map(|p| p[2]).collect(),
        }
    }

    /// Vector `i` as an array.
    pub fn get(&self, i: usize) -> [f32; 3] {
        [self.x[i], self.y[i], self.z[i]]
    }
}

/// `v` as packets of `lanes` 3-vectors in one flat buffer (array of structures of arrays):
/// packet `p` is `x[0..lanes], y[0..lanes], z[0..lanes]` of vectors `p * lanes ..`, the
/// memory layout of ultraviolet's `Vec3x8` and of `Vector<F32x8, U3>`. A last partial
/// packet is dropped.
pub fn aosoa(v: &[[f32; 3]], lanes: usize) -> Vec<f32> {
    v.chunks_exact(lanes)
        .flat_map(|c| (0..3).flat_map(move |k| c.iter().map(move |p| p[k])))
        .collect()
}

/// `f32`s whose first element is 64-byte aligned (a cache line, the alignment of an
/// AVX-512 register), so the packets of [`aosoa`] sit in memory as ultraviolet's
/// `Vec3x8` (aligned to 32 bytes by its type) and vecexpr's lane types do, and no
/// register load or store is split across cache lines.
#[derive(Clone, Debug)]
pub struct Aligned {
    buf: Vec<f32>,
    off: usize,
    len: usize,
}

impl Aligned {
    /// A 64-byte aligned copy of `v`.
    pub fn new(v: &[f32]) -> Self {
        let mut buf = vec![0.0f32; v.len() + 16];
        let off = buf.as_ptr().align_offset(64);
        assert!(off < 16, "no 64-byte aligned f32 within 16 elements");
        buf[off..off + v.len()].copy_from_slice(v);
        Self {
            buf,
            off,
            len: v.len(),
        }
    }

    /// The elements.
    pub fn as_slice(&self) -> &[f32] {
        &self.buf[self.off..self.off + self.len]
    }

    /// The elements, mutably.
    pub fn as_mut_slice(&mut self) -> &mut [f32] {
        &mut self.buf[self.off..self.off + self.len]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn deterministic_and_in_range() {
        let (mut a, mut b) = (Pcg32::new(7), Pcg32::new(7));
        for _ in 0..1000 {
            let x = a.range(-1.0, 1.0);
            assert_eq!(x, b.range(-1.0, 1.0));
            assert!((-1.0..1.0).contains(&x));
        }
        assert_ne!(Pcg32::new(1).next_u32(), Pcg32::new(2).next_u32());
        let u = a.unit3();
        assert!((u[0] * u[0] + u[1] * u[1] + u[2] * u[2] - 1.0).abs() < 1e-5);
        let v = a.vec3s(5);
        let s = Soa::from_aos(&v);
        assert_eq!(s.get(3), v[3]);
        let p = aosoa(&v, 2);
        assert_eq!(p.len(), 12);
        assert_eq!(
            p[6..12],
            [v[2][0], v[3][0], v[2][1], v[3][1], v[2][2], v[3][2]]
        );
    }
}
