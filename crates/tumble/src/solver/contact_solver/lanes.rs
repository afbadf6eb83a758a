//! The solver's one portable SIMD type: [`Lane`], four f64 lanes (the `wide`
//! crate's `f64x4`: one AVX register where the build targets AVX, two SSE2
//! registers otherwise), and the 3-vectors and 3 x 3 matrices made of them
//! that the wide patch kernels (`wide`) use to solve four contact patches at
//! once, one per lane.
//!
//! Every operation here performs, lane by lane, the same IEEE operations in
//! the same order as `glam`'s `DVec3` and `DMat3` (dot products summed left
//! to right, cross products and matrix-vector products as glam writes them),
//! and nothing is fused into a multiply-add: a lane of a wide kernel gives
//! the same bits as the scalar kernel on the same patch.
//!
//! `V3`, `M3` and `Q4` each spell out their gathers (`from_lanes`),
//! scatters (`to_lanes`) and arithmetic field by field, as glam writes its
//! own types, so each line can be held against the glam expression it must
//! match; `wide`'s `PairLanes::load` gathers the bodies' velocities alike.

use tumble_collide::{DMat3, DQuat, DVec3};
use wide::f64x4;

/// Four f64 lanes.
pub type Lane = f64x4;

/// Number of lanes of a [`Lane`].
pub const LANES: usize = 4;

/// Lanewise `a > b` as a mask (all bits set where true).
#[inline(always)]
pub fn gt(a: Lane, b: Lane) -> Lane {
    a.simd_gt(b)
}

/// Lanewise `a < b` as a mask.
#[inline(always)]
pub fn lt(a: Lane, b: Lane) -> Lane {
    a.simd_lt(b)
}

/// Lanewise `a <= b` as a mask.
#[inline(always)]
pub fn le(a: Lane, b: Lane) -> Lane {
    a.simd_le(b)
}

/// Lanewise `a == b` as a mask.
#[inline(always)]
pub fn eq(a: Lane, b: Lane) -> Lane {
    a.simd_eq(b)
}

/// Lanewise `if mask { yes } else { no }`.
#[inline(always)]
pub fn select(mask: Lane, yes: Lane, no: Lane) -> Lane {
    mask.select(yes, no)
}

/// A mask from one flag per lane.
#[inline(always)]
pub fn mask(flags: [bool; LANES]) -> Lane {
    Lane::new(flags.map(|f| if f { f64::from_bits(u64::MAX) } else { 0.0 }))
}

/// `1 / k` where `k > 0`, else 0 (as the scalar `recip_or_zero`).
#[inline(always)]
pub fn recip_or_zero(k: Lane) -> Lane {
    select(gt(k, Lane::ZERO), Lane::ONE / k, Lane::ZERO)
}

/// A 3-vector per lane, stored as three lanes (structure of arrays).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct V3 {
    /// x of every lane.
    pub x: Lane,
    /// y of every lane.
    pub y: Lane,
    /// z of every lane.
    pub z: Lane,
}

impl V3 {
    /// Zero in every lane.
    pub const ZERO: V3 = V3 {
        x: Lane::ZERO,
        y: Lane::ZERO,
        z: Lane::ZERO,
    };

    /// One vector per lane.
    #[inline(always)]
    pub fn from_lanes(v: [DVec3; LANES]) -> V3 {
        V3 {
            x: Lane::new(v.map(|v| v.x)),
            y: Lane::new(v.map(|v| v.y)),
            z: Lane::new(v.map(|v| v.z)),
        }
    }

    /// The vectors of the lanes.
    #[inline(always)]
    pub fn to_lanes(self) -> [DVec3; LANES] {
        let (x, y, z) = (self.x.to_array(), self.y.to_array(), self.z.to_array());
        std::array::from_fn(|l| DVec3::new(x[l], y[l], z[l]))
    }

    /// Sets lane `l` to `v`.
    #[inline(always)]
    pub fn set_lane(&mut self, l: usize, v: DVec3) {
        self.x.as_mut_array()[l] = v.x;
        self.y.as_mut_array()[l] = v.y;
        self.z.as_mut_array()[l] = v.z;
    }

    /// `(x x') + (y y') + (z z')`, as glam's `dot`.
    #[inline(always)]
    pub fn dot(self, o: V3) -> Lane {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// As glam's `cross`.
    #[inline(always)]
    pub fn cross(self, o: V3) -> V3 {
        V3 {
            x: self.y * o.z - o.y * self.z,
            y: self.z * o.x - o.z * self.x,
            z: self.x * o.y - o.x * self.y,
        }
    }

    /// Every component times the lane's scalar.
    #[inline(always)]
    pub fn scale(self, s: Lane) -> V3 {
        V3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }

    /// Component by component, as glam's `DVec3 * DVec3`.
    #[inline(always)]
    pub fn mul_each(self, o: V3) -> V3 {
        V3 {
            x: self.x * o.x,
            y: self.y * o.y,
            z: self.z * o.z,
        }
    }

    /// Component `axis` (0, 1, 2).
    #[inline(always)]
    pub fn component(self, axis: usize) -> Lane {
        match axis {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }

    /// Lanewise `self == other` (`DVec3`'s `==`: every component equal) as a mask.
    #[inline(always)]
    pub fn eq_mask(&self, other: &V3) -> Lane {
        eq(self.x, other.x) & eq(self.y, other.y) & eq(self.z, other.z)
    }

    /// Lanewise `if mask { yes } else { no }`.
    #[inline(always)]
    pub fn select(mask: Lane, yes: V3, no: V3) -> V3 {
        V3 {
            x: select(mask, yes.x, no.x),
            y: select(mask, yes.y, no.y),
            z: select(mask, yes.z, no.z),
        }
    }
}

impl std::ops::Add for V3 {
    type Output = V3;
    #[inline(always)]
    fn add(self, o: V3) -> V3 {
        V3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
}

impl std::ops::Sub for V3 {
    type Output = V3;
    #[inline(always)]
    fn sub(self, o: V3) -> V3 {
        V3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
}

impl std::ops::AddAssign for V3 {
    #[inline(always)]
    fn add_assign(&mut self, o: V3) {
        *self = *self + o;
    }
}

impl std::ops::SubAssign for V3 {
    #[inline(always)]
    fn sub_assign(&mut self, o: V3) {
        *self = *self - o;
    }
}

/// A 3 x 3 matrix per lane, by columns as glam's `DMat3`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct M3 {
    /// First column.
    pub x_axis: V3,
    /// Second column.
    pub y_axis: V3,
    /// Third column.
    pub z_axis: V3,
}

impl M3 {
    /// The identity in every lane.
    pub const IDENTITY: M3 = M3 {
        x_axis: V3 {
            x: Lane::ONE,
            y: Lane::ZERO,
            z: Lane::ZERO,
        },
        y_axis: V3 {
            x: Lane::ZERO,
            y: Lane::ONE,
            z: Lane::ZERO,
        },
        z_axis: V3 {
            x: Lane::ZERO,
            y: Lane::ZERO,
            z: Lane::ONE,
        },
    };

    /// Lanewise `self == other` (`DMat3`'s `==`: every entry equal) as a mask.
    #[inline(always)]
    pub fn eq_mask(&self, other: &M3) -> Lane {
        self.x_axis.eq_mask(&other.x_axis)
            & self.y_axis.eq_mask(&other.y_axis)
            & self.z_axis.eq_mask(&other.z_axis)
    }

    /// One matrix per lane.
    #[inline(always)]
    pub fn from_lanes(m: [DMat3; LANES]) -> M3 {
        M3 {
            x_axis: V3::from_lanes(m.map(|m| m.x_axis)),
            y_axis: V3::from_lanes(m.map(|m| m.y_axis)),
            z_axis: V3::from_lanes(m.map(|m| m.z_axis)),
        }
    }

    /// `M v` summed column by column, as glam's `mul_vec3`.
    #[inline(always)]
    pub fn mul_vec(&self, v: V3) -> V3 {
        self.x_axis.scale(v.x) + self.y_axis.scale(v.y) + self.z_axis.scale(v.z)
    }

    /// `M N`, column by column, as glam's `DMat3 * DMat3`.
    #[inline(always)]
    pub fn mul(&self, n: &M3) -> M3 {
        M3 {
            x_axis: self.mul_vec(n.x_axis),
            y_axis: self.mul_vec(n.y_axis),
            z_axis: self.mul_vec(n.z_axis),
        }
    }

    /// As glam's `transpose`.
    #[inline(always)]
    pub fn transpose(&self) -> M3 {
        let (x, y, z) = (self.x_axis, self.y_axis, self.z_axis);
        M3 {
            x_axis: V3 {
                x: x.x,
                y: y.x,
                z: z.x,
            },
            y_axis: V3 {
                x: x.y,
                y: y.y,
                z: z.y,
            },
            z_axis: V3 {
                x: x.z,
                y: y.z,
                z: z.z,
            },
        }
    }

    /// As glam's `DMat3::from_diagonal` (explicit zeros off the diagonal,
    /// so that products sum the same terms).
    #[inline(always)]
    pub fn diagonal(d: V3) -> M3 {
        let zero = Lane::ZERO;
        M3 {
            x_axis: V3 {
                x: d.x,
                y: zero,
                z: zero,
            },
            y_axis: V3 {
                x: zero,
                y: d.y,
                z: zero,
            },
            z_axis: V3 {
                x: zero,
                y: zero,
                z: d.z,
            },
        }
    }
}

/// A quaternion per lane (x, y, z, w), with glam's `DQuat` arithmetic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Q4 {
    /// x of every lane.
    pub x: Lane,
    /// y of every lane.
    pub y: Lane,
    /// z of every lane.
    pub z: Lane,
    /// w of every lane.
    pub w: Lane,
}

impl Q4 {
    /// One quaternion per lane.
    #[inline(always)]
    pub fn from_lanes(q: [DQuat; LANES]) -> Q4 {
        Q4 {
            x: Lane::new(q.map(|q| q.x)),
            y: Lane::new(q.map(|q| q.y)),
            z: Lane::new(q.map(|q| q.z)),
            w: Lane::new(q.map(|q| q.w)),
        }
    }

    /// The quaternions of the lanes.
    #[inline(always)]
    pub fn to_lanes(self) -> [DQuat; LANES] {
        let (x, y, z, w) = (
            self.x.to_array(),
            self.y.to_array(),
            self.z.to_array(),
            self.w.to_array(),
        );
        std::array::from_fn(|l| DQuat::from_xyzw(x[l], y[l], z[l], w[l]))
    }

    /// As glam's `mul_quat`: `self * rhs`.
    #[inline(always)]
    pub fn mul(self, rhs: Q4) -> Q4 {
        let (x0, y0, z0, w0) = (self.x, self.y, self.z, self.w);
        let (x1, y1, z1, w1) = (rhs.x, rhs.y, rhs.z, rhs.w);
        Q4 {
            x: w0 * x1 + x0 * w1 + y0 * z1 - z0 * y1,
            y: w0 * y1 - x0 * z1 + y0 * w1 + z0 * x1,
            z: w0 * z1 + x0 * y1 - y0 * x1 + z0 * w1,
            w: w0 * w1 - x0 * x1 - y0 * y1 - z0 * z1,
        }
    }

    /// `self * v`, the vector turned, as glam's `DQuat::mul_vec3`.
    #[inline(always)]
    pub fn rotate(self, v: V3) -> V3 {
        let w = self.w;
        let b = V3 {
            x: self.x,
            y: self.y,
            z: self.z,
        };
        let b2 = b.dot(b);
        let two = Lane::splat(2.0);
        v.scale(w * w - b2) + b.scale(v.dot(b) * two) + b.cross(v).scale(w * two)
    }

    /// Lanewise `if mask { yes } else { no }`.
    #[inline(always)]
    pub fn select(mask: Lane, yes: Q4, no: Q4) -> Q4 {
        Q4 {
            x: select(mask, yes.x, no.x),
            y: select(mask, yes.y, no.y),
            z: select(mask, yes.z, no.z),
            w: select(mask, yes.w, no.w),
        }
    }

    /// As glam's `conjugate`.
    #[inline(always)]
    pub fn conjugate(self) -> Q4 {
        Q4 {
            x: -self.x,
            y: -self.y,
            z: -self.z,
            w: self.w,
        }
    }

    /// As glam's `normalize`: times the reciprocal of the length.
    #[inline(always)]
    pub fn normalize(self) -> Q4 {
        let dot = self.x * self.x + self.y * self.y + self.z * self.z + self.w * self.w;
        let recip = Lane::ONE / dot.sqrt();
        Q4 {
            x: self.x * recip,
            y: self.y * recip,
            z: self.z * recip,
            w: self.w * recip,
        }
    }

    /// The rotation matrix, as glam's `DMat3::from_quat`.
    #[inline(always)]
    pub fn to_mat3(self) -> M3 {
        let (x2, y2, z2) = (self.x + self.x, self.y + self.y, self.z + self.z);
        let (xx, xy, xz) = (self.x * x2, self.x * y2, self.x * z2);
        let (yy, yz, zz) = (self.y * y2, self.y * z2, self.z * z2);
        let (wx, wy, wz) = (self.w * x2, self.w * y2, self.w * z2);
        let one = Lane::ONE;
        M3 {
            x_axis: V3 {
                x: one - (yy + zz),
                y: xy + wz,
                z: xz - wy,
            },
            y_axis: V3 {
                x: xy - wz,
                y: one - (xx + zz),
                z: yz + wx,
            },
            z_axis: V3 {
                x: xz + wy,
                y: yz - wx,
                z: one - (xx + yy),
            },
        }
    }
}

impl M3 {
    /// The matrices of the lanes.
    #[inline(always)]
    pub fn to_lanes(self) -> [DMat3; LANES] {
        let (x, y, z) = (
            self.x_axis.to_lanes(),
            self.y_axis.to_lanes(),
            self.z_axis.to_lanes(),
        );
        std::array::from_fn(|l| DMat3::from_cols(x[l], y[l], z[l]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tumble_testkit::{RandomSource, SplitMix64};

    /// Each lane of every operation is bit for bit what glam computes.
    #[test]
    fn lanes_compute_glams_bits() {
        let mut rng = SplitMix64(7);
        for _ in 0..200 {
            let a: [DVec3; LANES] = std::array::from_fn(|_| rng.vec3(3.0));
            let b: [DVec3; LANES] = std::array::from_fn(|_| rng.vec3(3.0));
            let m: [DMat3; LANES] =
                std::array::from_fn(|_| DMat3::from_cols(rng.vec3(3.0), rng.vec3(3.0), rng.vec3(3.0)));
            let (wa, wb, wm) = (V3::from_lanes(a), V3::from_lanes(b), M3::from_lanes(m));
            let dot = wa.dot(wb).to_array();
            let cross = wa.cross(wb).to_lanes();
            let product = wm.mul_vec(wa).to_lanes();
            let q: [DQuat; LANES] = std::array::from_fn(|_| rng.rotation() * 1.3);
            let r: [DQuat; LANES] = std::array::from_fn(|_| rng.rotation());
            let (wq, wr) = (Q4::from_lanes(q), Q4::from_lanes(r));
            let (prod, conj, unit) = (
                wq.mul(wr).to_lanes(),
                wq.conjugate().to_lanes(),
                wq.normalize().to_lanes(),
            );
            let mats = wr.to_mat3().to_lanes();
            let turned = wr.rotate(wa).to_lanes();
            let each = wa.mul_each(wb).to_lanes();
            let n = M3::from_lanes(std::array::from_fn(|l| DMat3::from_quat(r[l])));
            let (mm, tr, diag) = (
                wm.mul(&n).to_lanes(),
                wm.transpose().to_lanes(),
                wm.mul(&M3::diagonal(wb)).to_lanes(),
            );
            for l in 0..LANES {
                assert_eq!(turned[l], r[l] * a[l]);
                assert_eq!(each[l], a[l] * b[l]);
                assert_eq!(mm[l], m[l] * DMat3::from_quat(r[l]));
                assert_eq!(tr[l], m[l].transpose());
                assert_eq!(diag[l], m[l] * DMat3::from_diagonal(b[l]));
                for (k, x) in a[l].to_array().into_iter().enumerate() {
                    assert_eq!(wa.component(k).to_array()[l].to_bits(), x.to_bits());
                }
                assert_eq!(dot[l].to_bits(), a[l].dot(b[l]).to_bits());
                assert_eq!(cross[l], a[l].cross(b[l]));
                assert_eq!(product[l], m[l] * a[l]);
                assert_eq!(prod[l], q[l] * r[l]);
                assert_eq!(conj[l], q[l].conjugate());
                assert_eq!(unit[l], q[l].normalize());
                assert_eq!(mats[l], DMat3::from_quat(r[l]));
            }
        }
    }

    #[test]
    fn masks_select_lane_by_lane() {
        let m = mask([true, false, false, true]);
        let r = select(m, Lane::splat(1.0), Lane::splat(2.0)).to_array();
        assert_eq!(r, [1.0, 2.0, 2.0, 1.0]);
        assert_eq!(
            recip_or_zero(Lane::new([2.0, 0.0, -1.0, 4.0])).to_array(),
            [0.5, 0.0, 0.0, 0.25]
        );
        assert!(gt(Lane::splat(1.0), Lane::ZERO).all());
        assert!(!lt(Lane::splat(1.0), Lane::ZERO).any());
        assert!(le(Lane::ZERO, Lane::ZERO).all() && eq(Lane::ZERO, Lane::splat(-0.0)).all());
    }

    /// `eq_mask` sets a lane exactly where glam's `==` holds: a signed
    /// zero equals zero, NaN equals nothing, one entry off is enough
    /// (what `wide::begin` asks of a lane's displacement and turn).
    #[test]
    fn equality_masks_agree_with_glams_eq() {
        let m = |d: f64, entry: usize| {
            let mut cols = DMat3::IDENTITY.to_cols_array();
            cols[entry] += d;
            DMat3::from_cols_array(&cols)
        };
        let mut cases = vec![
            (DMat3::IDENTITY, DVec3::ZERO),
            (DMat3::IDENTITY, DVec3::new(-0.0, 0.0, -0.0)),
        ];
        for entry in 0..9 {
            cases.push((m(1e-300, entry), DVec3::ZERO));
            cases.push((m(f64::NAN, entry), DVec3::ZERO));
            cases.push((m(-1e-16, entry), DVec3::new(0.0, 0.0, f64::MIN_POSITIVE)));
        }
        cases.push((DMat3::IDENTITY, DVec3::new(f64::NAN, 0.0, 0.0)));
        cases.push((DMat3::IDENTITY, DVec3::new(0.0, -1e-300, 0.0)));
        for four in cases.chunks(LANES) {
            let (ms, vs): (Vec<DMat3>, Vec<DVec3>) = four.iter().copied().unzip();
            let pad = |k: usize| k.min(four.len() - 1);
            let ms: [DMat3; LANES] = std::array::from_fn(|l| ms[pad(l)]);
            let vs: [DVec3; LANES] = std::array::from_fn(|l| vs[pad(l)]);
            let at_rest = M3::from_lanes(ms).eq_mask(&M3::IDENTITY) & V3::from_lanes(vs).eq_mask(&V3::ZERO);
            let bits = at_rest.to_array();
            for l in 0..LANES {
                let glam = ms[l] == DMat3::IDENTITY && vs[l] == DVec3::ZERO;
                assert_eq!(bits[l].to_bits() != 0, glam, "lane {l}: {:?}, {:?}", ms[l], vs[l]);
            }
        }
    }
}
