//! The pinhole camera of the thesis: position $C_p$, direction $C_d$, up $C_u$ and left
//! $C_l$, with the angle of view and aspect folded into the lengths of $C_u$ and $C_l$;
//! and where in a pixel its eye rays pass ([`Grid`]): every image-plane point the
//! renderers, the packets and the viewer trace through is computed here.

use crate::ray::Ray;
use crate::scene::desc::CameraDesc;
use vecexpr::{vec3, Expr, Mat3, Real, Scalar, Vec3};

/// A camera for an image of a given size.
///
/// For image-plane coordinates $(\hat x, \hat y)$ in pixels (continuous: pixel $(i, j)$
/// covers $[i, i+1) \times [j, j+1)$), $x = 2\hat x / w - 1$ and $y = 1 - 2\hat y / h$,
/// and the ray direction is $\mathrm{normalize}(C_d + C_l x + C_u y)$, the product of the
/// basis matrix $B = [C_d\ C_l\ C_u]$ (columns) with $(1, x, y)$, where
/// $|C_u| = \tan(\alpha/2)$ and $|C_l| = \frac{w}{h}\tan(\alpha/2)$ for the vertical
/// angle of view $\alpha$. So the vertical angle stays fixed when the width changes.
///
/// NFF measures the angle between the centres of the top and bottom pixel rows; here it
/// spans the image edges, a difference of one pixel in $h$. $C_l$ points to the image's
/// right-hand side ($x > 0$) so that a right-handed scene is seen unmirrored.
#[derive(Clone, Copy, Debug)]
pub struct Camera<T: Real> {
    /// Eye position $C_p$.
    pub position: Vec3<T>,
    /// The basis $B = [C_d\ C_l\ C_u]$ as columns: the unit view direction $C_d$, the
    /// image-plane horizontal vector $C_l$ of length $\frac{w}{h}\tan(\alpha/2)$ and the
    /// image-plane up vector $C_u$ of length $\tan(\alpha/2)$. Column order and the
    /// $(1, x, y)$ coordinates make $B (1, x, y)$ sum as $(C_d + C_l x) + C_u y$.
    pub basis: Mat3<T>,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl<T: Real> Camera<T> {
    /// Builds the camera from NFF's `from`, `at`, `up`, `angle` for a `width` x `height`
    /// image. A degenerate `up` (parallel to the view direction) is replaced by the axis
    /// least aligned with the view.
    pub fn new(desc: &CameraDesc, width: u32, height: u32) -> Self {
        let c = |p: [f64; 3]| vec3(T::from_f64(p[0]), T::from_f64(p[1]), T::from_f64(p[2]));
        let position = c(desc.from);
        let dir = (c(desc.at) - &position).normalize();
        let mut right = dir.cross(&c(desc.up));
        if right.length_squared() <= T::EPSILON * T::EPSILON {
            // up is parallel to the view: pick the axis least aligned with dir.
            let a = dir.abs().eval();
            let axis = if a[0] <= a[1] && a[0] <= a[2] {
                0
            } else if a[1] <= a[2] {
                1
            } else {
                2
            };
            right = dir.cross(&Vec3::<T>::unit(axis));
        }
        let right = right.normalize();
        let up = right.cross(&dir);
        let half = T::from_f64((desc.angle_deg.to_radians() * 0.5).tan());
        let aspect = T::from_f64(width as f64 / height.max(1) as f64);
        Self {
            position,
            basis: Mat3::from_cols([
                dir,
                (&right).scale(half * aspect).eval(),
                (&up).scale(half).eval(),
            ]),
            width,
            height,
        }
    }

    /// The unit direction through image-plane point $(\hat x, \hat y)$ (pixels).
    #[inline]
    pub fn direction(&self, px: T, py: T) -> Vec3<T> {
        direction(&self.basis, self.size(), px, py)
    }

    /// The image size as two values of `T`, the divisors of [`Camera::direction`].
    #[inline]
    fn size(&self) -> (T, T) {
        (
            T::from_f64(self.width as f64),
            T::from_f64(self.height as f64),
        )
    }

    /// The unit view direction $C_d$ (the basis' first column).
    #[inline]
    pub fn dir(&self) -> &Vec3<T> {
        self.basis.col(0)
    }

    /// The image-plane horizontal vector $C_l$ (second column).
    #[inline]
    pub fn left(&self) -> &Vec3<T> {
        self.basis.col(1)
    }

    /// The image-plane up vector $C_u$ (third column).
    #[inline]
    pub fn up(&self) -> &Vec3<T> {
        self.basis.col(2)
    }

    /// The eye ray through image-plane point $(\hat x, \hat y)$ (pixels).
    #[inline]
    pub fn ray(&self, px: T, py: T) -> Ray<T> {
        Ray::new(self.position, self.direction(px, py))
    }
}

#[cfg(target_arch = "x86_64")]
impl Camera<f32> {
    /// The eye rays through the image-plane points `(px[i], py[i])`, four at a time on an
    /// SSE register: ray `i` is [`Camera::ray`]`(px[i], py[i])` bit for bit, since both
    /// run the one formula of [`Camera::direction`] over `vecexpr`'s scalars (its matrix
    /// product and `normalize`, whose slow path for extreme lengths is taken lane by
    /// lane). One ray at a time, the two divisions, the square root and
    /// the reciprocal of `normalize` were 12 % of a render's samples on tetra-s6.
    #[inline]
    pub fn rays4(&self, px: &[f32; 4], py: &[f32; 4]) -> [Ray<f32>; 4] {
        use vecexpr::simd::{F32x4, SimdF32};
        let sp = F32x4::splat;
        let cols: [Vec3<F32x4>; 3] = core::array::from_fn(|c| {
            let v = self.basis.col(c);
            vec3(sp(v[0]), sp(v[1]), sp(v[2]))
        });
        let (w, h) = self.size();
        let (px, py) = (F32x4::load(px), F32x4::load(py));
        let d = direction(&Mat3::from_cols(cols), (sp(w), sp(h)), px, py);
        let mut lanes = [[0.0f32; 4]; 3];
        for (l, v) in lanes.iter_mut().zip([&d[0], &d[1], &d[2]]) {
            v.store(l);
        }
        core::array::from_fn(|i| {
            Ray::new(self.position, vec3(lanes[0][i], lanes[1][i], lanes[2][i]))
        })
    }
}

/// The formula of [`Camera::direction`] for a `basis` and an image `size`, written once
/// over `vecexpr`'s scalars: `f32` or `f64` for one ray, SIMD lanes for several
/// ([`Camera::rays4`]), with the same operations in the same order in each lane.
#[inline(always)]
fn direction<S: Scalar>(basis: &Mat3<S>, (w, h): (S, S), px: S, py: S) -> Vec3<S> {
    let (two, one) = (S::splat_f64(2.0), S::splat_f64(1.0));
    let x = two * px / w - one;
    let y = one - two * py / h;
    (basis * vec3(one, x, y)).normalize()
}

/// The points of an image grid that eye rays pass through: grid point `(x, y)` is a
/// pixel (or, for [`Grid::Corners`], a pixel corner).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grid {
    /// The pixel centre `(x + 1/2, y + 1/2)`.
    Centers,
    /// The pixel corner `(x, y)` (SPD mode: a `(w + 1) x (h + 1)` grid).
    Corners,
    /// Sample `(i, j)` of the regular `a` x `a` grid of supersamples in the pixel:
    /// `(x + (i + 1/2) / a, y + (j + 1/2) / a)`.
    Sample {
        /// Column of the sample in the pixel.
        i: u32,
        /// Row of the sample in the pixel.
        j: u32,
        /// Samples per pixel and axis.
        a: u32,
    },
}

impl Grid {
    /// The image-plane point of grid point `(x, y)`.
    #[inline(always)]
    pub fn point<T: Real>(self, x: usize, y: usize) -> (T, T) {
        let (x, y) = (T::from_f64(x as f64), T::from_f64(y as f64));
        match self {
            // (0 + 1/2) * 1 = 1/2 exactly: the centre is sample (0, 0) of one.
            Self::Centers => {
                let half = sample_offset::<T>(0, 1);
                (x + half, y + half)
            }
            Self::Corners => (x, y),
            Self::Sample { i, j, a } => {
                (x + sample_offset::<T>(i, a), y + sample_offset::<T>(j, a))
            }
        }
    }
}

/// A rectangle of an image grid: `size` points from `origin`, row-major. Grid point
/// `(x, y)` of the window is point `origin + (x, y)` of the whole grid, so a window's
/// points are exactly the points of the full grid it covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Window {
    /// The first column and row in the whole grid.
    pub origin: (usize, usize),
    /// Columns and rows.
    pub size: (usize, usize),
}

impl Window {
    /// The whole `w` x `h` grid.
    pub fn full((w, h): (usize, usize)) -> Self {
        Self {
            origin: (0, 0),
            size: (w, h),
        }
    }

    /// The image-plane point of point `(x, y)` of the window in `grid`.
    #[inline(always)]
    pub fn point<T: Real>(&self, grid: Grid, x: usize, y: usize) -> (T, T) {
        grid.point(self.origin.0 + x, self.origin.1 + y)
    }
}

/// Where sample `i` of `a` lies along one axis of a pixel: $(i + 1/2) / a$, computed as
/// $(i + 1/2) \cdot (1/a)$.
#[inline(always)]
pub fn sample_offset<T: Real>(i: u32, a: u32) -> T {
    let a = a.max(1);
    (T::from_f64(i as f64) + T::from_f64(0.5)) * T::from_f64(1.0 / a as f64)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four rays at a time are the single rays, bit for bit: pixel centres, corners and
    /// supersamples of small and odd images, cameras looking along and across the axes,
    /// a wide and a narrow angle, and points far outside the image (large and extreme
    /// directions, which take `normalize`'s slow path in some lanes).
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn four_rays_at_a_time_are_the_single_rays() {
        let cams = [
            (
                [0.0, 0.0, 5.0],
                [0.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                45.0,
                (512, 512),
            ),
            (
                [2.1, 1.3, 2.5],
                [0.0, 0.0, 0.0],
                [0.0, 0.0, 1.0],
                20.0,
                (640, 480),
            ),
            (
                [-3.0, 7.0, 0.5],
                [1.0, -2.0, 0.0],
                [0.0, 1.0, 0.0],
                120.0,
                (17, 9),
            ),
            (
                [0.0, 0.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 1.0, 0.0],
                1.0,
                (3, 1000),
            ),
        ];
        let mut checked = 0;
        for (from, at, up, angle_deg, (w, h)) in cams {
            let desc = CameraDesc {
                from,
                at,
                up,
                angle_deg,
                hither: 0.0,
                resolution: (w, h),
            };
            let cam = Camera::<f32>::new(&desc, w, h);
            let mut points: Vec<(f32, f32)> = Vec::new();
            for grid in [
                Grid::Centers,
                Grid::Corners,
                Grid::Sample { i: 1, j: 2, a: 3 },
            ] {
                for y in (0..h as usize).step_by(h as usize / 7 + 1) {
                    for x in (0..w as usize).step_by(w as usize / 7 + 1) {
                        points.push(grid.point(x, y));
                    }
                }
            }
            points.extend([(-1e6, 3.0), (1e30, -1e30), (0.5, f32::MAX), (-0.0, 1e-40)]);
            while !points.len().is_multiple_of(4) {
                points.push((0.25, 0.75));
            }
            for p in points.chunks(4) {
                let px = [p[0].0, p[1].0, p[2].0, p[3].0];
                let py = [p[0].1, p[1].1, p[2].1, p[3].1];
                for (i, r) in cam.rays4(&px, &py).iter().enumerate() {
                    let single = cam.ray(px[i], py[i]);
                    let bits = |r: &Ray<f32>| {
                        let (o, d) = (&r.origin, &r.dir);
                        [o[0], o[1], o[2], d[0], d[1], d[2], r.t_min, r.t_max].map(f32::to_bits)
                    };
                    assert_eq!(bits(r), bits(&single), "({}, {})", px[i], py[i]);
                    checked += 1;
                }
            }
        }
        assert!(checked > 200, "{checked}");
    }
}
