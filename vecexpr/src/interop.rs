//! Conversions to and from other crates' types, each behind an optional cargo feature.
//!
//! - `mint`: `From`/`Into` between [`Vector<T, U2 | U3 | U4>`](crate::Vector) and
//!   `mint::Vector2/3/4<T>`, and between [`Matrix<T, R, C>`](crate::Matrix) and
//!   `mint::ColumnMatrix{R}x{C}<T>` (`ColumnMatrix2/3/4` for square ones) for `R` and `C`
//!   in 2..=4, plus `mint::IntoMint`, so vecexpr values pass straight to APIs that take
//!   `impl Into<mint::Vector3<f32>>` (glam, nalgebra, cgmath, ... with their `mint`
//!   features).
//! - `serde`: `Serialize`/`Deserialize` for `Vector<T, N>` as a tuple of `N` elements
//!   (`[1.0,2.0,3.0]` in JSON), and for `Matrix<T, R, C>` as a tuple of its `C` columns,
//!   each a tuple of `R` elements (column-major, the storage order). Deserialising checks
//!   the lengths: a 2-element sequence is not a 3-vector.

#[cfg(feature = "mint")]
mod mint_impls {
    use crate::{Matrix, Vector};
    use typenum::{U2, U3, U4};

    macro_rules! vector {
        ($n:ty, $m:ident, $($f:ident),+) => {
            impl<T> From<mint::$m<T>> for Vector<T, $n> {
                #[inline]
                fn from(v: mint::$m<T>) -> Self {
                    Vector::from([$(v.$f),+])
                }
            }
            impl<T> From<Vector<T, $n>> for mint::$m<T> {
                #[inline]
                fn from(v: Vector<T, $n>) -> Self {
                    let [$($f),+] = v.into_array();
                    mint::$m { $($f),+ }
                }
            }
            impl<T> mint::IntoMint for Vector<T, $n> {
                type MintType = mint::$m<T>;
            }
        };
    }
    vector!(U2, Vector2, x, y);
    vector!(U3, Vector3, x, y, z);
    vector!(U4, Vector4, x, y, z, w);

    macro_rules! matrix {
        ($r:ty, $c:ty, $m:ident, $($f:ident),+) => {
            impl<T> From<mint::$m<T>> for Matrix<T, $r, $c> {
                #[inline]
                fn from(m: mint::$m<T>) -> Self {
                    Matrix::from_cols([$(Vector::from(m.$f)),+])
                }
            }
            impl<T> From<Matrix<T, $r, $c>> for mint::$m<T> {
                #[inline]
                fn from(m: Matrix<T, $r, $c>) -> Self {
                    let [$($f),+] = m.into_cols().into_array();
                    mint::$m { $($f: $f.into()),+ }
                }
            }
            impl<T> mint::IntoMint for Matrix<T, $r, $c> {
                type MintType = mint::$m<T>;
            }
        };
    }
    // mint names a column matrix by rows then columns; its fields are the columns.
    matrix!(U2, U2, ColumnMatrix2, x, y);
    matrix!(U3, U3, ColumnMatrix3, x, y, z);
    matrix!(U4, U4, ColumnMatrix4, x, y, z, w);
    matrix!(U2, U3, ColumnMatrix2x3, x, y, z);
    matrix!(U2, U4, ColumnMatrix2x4, x, y, z, w);
    matrix!(U3, U2, ColumnMatrix3x2, x, y);
    matrix!(U3, U4, ColumnMatrix3x4, x, y, z, w);
    matrix!(U4, U2, ColumnMatrix4x2, x, y);
    matrix!(U4, U3, ColumnMatrix4x3, x, y, z);

    #[cfg(test)]
    mod tests {
        use crate::{vec2, vec3, vec4, Expr, Mat3, Matrix, Vector};
        use typenum::{U2, U3, U4};

        /// A function taking any `mint` vector, as the APIs of other crates do.
        fn length(v: impl Into<mint::Vector3<f64>>) -> f64 {
            let v: mint::Vector3<f64> = v.into();
            (v.x * v.x + v.y * v.y + v.z * v.z).sqrt()
        }

        #[test]
        fn vectors_round_trip() {
            let m: mint::Vector3<f32> = vec3(1.0f32, 2.0, 3.0).into();
            assert_eq!((m.x, m.y, m.z), (1.0, 2.0, 3.0));
            assert_eq!(Vector::<f32, U3>::from(m), vec3(1.0, 2.0, 3.0));
            let m2: mint::Vector2<f64> = vec2(1.0, -1.0).into();
            assert_eq!(Vector::from(m2), vec2(1.0f64, -1.0));
            let m4 = mint::Vector4 {
                x: 1.0f32,
                y: 2.0,
                z: 3.0,
                w: 4.0,
            };
            assert_eq!(Vector::<f32, U4>::from(m4), vec4(1.0, 2.0, 3.0, 4.0));
            assert_eq!(length(vec3(3.0f64, 4.0, 0.0)), 5.0);
            assert_eq!(length(vec3(2.0f64, 0.0, 0.0).normalize()), 1.0);
        }

        #[test]
        fn matrices_are_columns() {
            let m = Matrix::from_rows([vec3(1.0f32, 2.0, 3.0), vec3(4.0, 5.0, 6.0)]);
            let c: mint::ColumnMatrix2x3<f32> = m.into();
            assert_eq!((c.x.x, c.x.y), (1.0, 4.0));
            assert_eq!((c.z.x, c.z.y), (3.0, 6.0));
            assert_eq!(Matrix::<f32, U2, U3>::from(c), m);
            let i: mint::ColumnMatrix3<f64> = Mat3::identity().into();
            assert_eq!((i.x.x, i.y.x, i.y.y), (1.0, 0.0, 1.0));
            assert_eq!(Mat3::<f64>::from(i), Mat3::identity());
            let t = Matrix::<f64, U4, U2>::from_fn(|r, c| (r * 2 + c) as f64);
            let tm: mint::ColumnMatrix4x2<f64> = t.into();
            assert_eq!((tm.y.w, tm.x.z), (7.0, 4.0));
            assert_eq!(Matrix::from(tm), t);
        }
    }
}

#[cfg(feature = "serde")]
mod serde_impls {
    use crate::{Matrix, Vector};
    use generic_array::{ArrayLength, GenericArray};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};

    /// A tuple of `N` elements.
    impl<T: Serialize, N: ArrayLength> Serialize for Vector<T, N> {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            self.as_generic_array().serialize(s)
        }
    }

    /// A tuple of exactly `N` elements.
    impl<'de, T: Deserialize<'de>, N: ArrayLength> Deserialize<'de> for Vector<T, N> {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            GenericArray::<T, N>::deserialize(d).map(Vector::from_generic_array)
        }
    }

    /// A tuple of the `C` columns, each a tuple of `R` elements.
    impl<T: Serialize, R: ArrayLength, C: ArrayLength> Serialize for Matrix<T, R, C> {
        fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
            self.col_array().serialize(s)
        }
    }

    /// A tuple of exactly `C` columns of exactly `R` elements.
    impl<'de, T: Deserialize<'de>, R: ArrayLength, C: ArrayLength> Deserialize<'de>
        for Matrix<T, R, C>
    {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
            GenericArray::<Vector<T, R>, C>::deserialize(d).map(Matrix::from_col_array)
        }
    }

    #[cfg(test)]
    mod tests {
        use crate::{vec2, vec3, Matrix, Vec3, Vector};
        use typenum::{U2, U3};

        #[test]
        fn vectors_are_tuples() {
            let v = vec3(1.0f32, -2.5, 3.0);
            let s = serde_json::to_string(&v).unwrap();
            assert_eq!(s, "[1.0,-2.5,3.0]");
            assert_eq!(serde_json::from_str::<Vec3<f32>>(&s).unwrap(), v);
            // The length is checked.
            assert!(serde_json::from_str::<Vec3<f64>>("[1.0,2.0]").is_err());
            assert!(serde_json::from_str::<Vec3<f64>>("[1.0,2.0,3.0,4.0]").is_err());
            let w: Vector<f64, U2> = serde_json::from_str("[0.5, 1e300]").unwrap();
            assert_eq!(w, vec2(0.5, 1e300));
        }

        #[test]
        fn matrices_are_columns() {
            let m = Matrix::from_rows([vec3(1.0f64, 2.0, 3.0), vec3(4.0, 5.0, 6.0)]);
            let s = serde_json::to_string(&m).unwrap();
            assert_eq!(s, "[[1.0,4.0],[2.0,5.0],[3.0,6.0]]");
            assert_eq!(serde_json::from_str::<Matrix<f64, U2, U3>>(&s).unwrap(), m);
            assert!(serde_json::from_str::<Matrix<f64, U3, U2>>(&s).is_err());
        }
    }
}
