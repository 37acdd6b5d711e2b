//! The integers exact elements are made of: `i128` near the origin copy
//! (checked, never wrapped) and [`BigInt`] beyond, so exact ids reach any
//! distance (up to [`MAX_BITS`], about distance 5,600, to bound memory).

use core::fmt::Debug;
use core::hash::Hash;

/// Most bits a [`BigInt`] may have: an element this far (about distance
/// 5,600 from the origin copy) is reported too far instead.
pub const MAX_BITS: usize = 1 << 13;

/// What golden arithmetic needs of an integer type.
pub(crate) trait Int: Clone + Eq + Hash + Debug {
    fn zero() -> Self;
    fn one() -> Self;
    /// `None` on overflow (never for [`BigInt`] below [`MAX_BITS`]).
    fn add(&self, o: &Self) -> Option<Self>;
    fn mul(&self, o: &Self) -> Option<Self>;
    fn is_even(&self) -> bool;
    /// Halves an even value exactly.
    fn half(&self) -> Self;
    fn to_f64(&self) -> f64;
    fn to_big(&self) -> BigInt;
}

impl Int for i128 {
    fn zero() -> Self {
        0
    }
    fn one() -> Self {
        1
    }
    fn add(&self, o: &Self) -> Option<Self> {
        self.checked_add(*o)
    }
    fn mul(&self, o: &Self) -> Option<Self> {
        self.checked_mul(*o)
    }
    // Bit operations, not `% 2` and `/ 2`: those are library calls on
    // `i128`. An even value shifted right is halved exactly, negative too.
    fn is_even(&self) -> bool {
        self & 1 == 0
    }
    fn half(&self) -> Self {
        self >> 1
    }
    fn to_f64(&self) -> f64 {
        *self as f64
    }
    fn to_big(&self) -> BigInt {
        BigInt::from_i128(*self)
    }
}

/// A signed integer of any size: sign and magnitude, little-endian 32-bit
/// limbs, no leading zero limb, zero not negative (so `==` and `Hash` are
/// on the value).
#[derive(Clone, Debug, PartialEq, Eq, Hash, Default)]
pub struct BigInt {
    negative: bool,
    limbs: Vec<u32>,
}

impl BigInt {
    /// The value of an `i128`.
    #[must_use]
    pub fn from_i128(x: i128) -> Self {
        let mut m = x.unsigned_abs();
        let mut limbs = Vec::new();
        while m != 0 {
            limbs.push(m as u32);
            m >>= 32;
        }
        BigInt { negative: x < 0, limbs }
    }

    /// The value as an `i128`, when it fits.
    #[must_use]
    pub fn to_i128(&self) -> Option<i128> {
        if self.limbs.len() > 4 {
            return None;
        }
        let m = self.limbs.iter().rev().fold(0u128, |m, &l| (m << 32) | u128::from(l));
        if self.negative {
            (m <= 1u128 << 127).then(|| (m as i128).wrapping_neg())
        } else {
            i128::try_from(m).ok()
        }
    }

    /// The sign and the little-endian 32-bit limbs of the magnitude.
    #[must_use]
    pub fn parts(&self) -> (bool, &[u32]) {
        (self.negative, &self.limbs)
    }

    fn normalized(mut self) -> Self {
        while self.limbs.last() == Some(&0) {
            self.limbs.pop();
        }
        if self.limbs.is_empty() {
            self.negative = false;
        }
        self
    }

    fn bits(&self) -> usize {
        self.limbs.len() * 32
    }
}

fn add_mag(a: &[u32], b: &[u32]) -> Vec<u32> {
    let (long, short) = if a.len() >= b.len() { (a, b) } else { (b, a) };
    let mut out = Vec::with_capacity(long.len() + 1);
    let mut carry = 0u64;
    for (i, &x) in long.iter().enumerate() {
        let s = u64::from(x) + u64::from(short.get(i).copied().unwrap_or(0)) + carry;
        out.push(s as u32);
        carry = s >> 32;
    }
    if carry != 0 {
        out.push(carry as u32);
    }
    out
}

/// `a - b` for `|a| >= |b|`.
fn sub_mag(a: &[u32], b: &[u32]) -> Vec<u32> {
    let mut out = Vec::with_capacity(a.len());
    let mut borrow = 0i64;
    for (i, &x) in a.iter().enumerate() {
        let mut d = i64::from(x) - i64::from(b.get(i).copied().unwrap_or(0)) - borrow;
        borrow = i64::from(d < 0);
        if d < 0 {
            d += 1 << 32;
        }
        out.push(d as u32);
    }
    out
}

fn cmp_mag(a: &[u32], b: &[u32]) -> core::cmp::Ordering {
    a.len().cmp(&b.len()).then_with(|| a.iter().rev().cmp(b.iter().rev()))
}

impl Int for BigInt {
    fn zero() -> Self {
        BigInt::default()
    }
    fn one() -> Self {
        BigInt::from_i128(1)
    }
    fn add(&self, o: &Self) -> Option<Self> {
        let r = if self.negative == o.negative {
            BigInt {
                negative: self.negative,
                limbs: add_mag(&self.limbs, &o.limbs),
            }
        } else if cmp_mag(&self.limbs, &o.limbs).is_ge() {
            BigInt {
                negative: self.negative,
                limbs: sub_mag(&self.limbs, &o.limbs),
            }
        } else {
            BigInt {
                negative: o.negative,
                limbs: sub_mag(&o.limbs, &self.limbs),
            }
        }
        .normalized();
        (r.bits() <= MAX_BITS).then_some(r)
    }
    fn mul(&self, o: &Self) -> Option<Self> {
        if self.bits() + o.bits() > MAX_BITS + 64 {
            return None;
        }
        let mut out = vec![0u32; self.limbs.len() + o.limbs.len()];
        for (i, &x) in self.limbs.iter().enumerate() {
            let mut carry = 0u64;
            for (j, &y) in o.limbs.iter().enumerate() {
                let t = u64::from(out[i + j]) + u64::from(x) * u64::from(y) + carry;
                out[i + j] = t as u32;
                carry = t >> 32;
            }
            out[i + o.limbs.len()] = carry as u32;
        }
        let r = BigInt {
            negative: self.negative != o.negative,
            limbs: out,
        }
        .normalized();
        (r.bits() <= MAX_BITS).then_some(r)
    }
    fn is_even(&self) -> bool {
        self.limbs.first().is_none_or(|l| l & 1 == 0)
    }
    fn half(&self) -> Self {
        let mut limbs = self.limbs.clone();
        let mut carry = 0u32;
        for l in limbs.iter_mut().rev() {
            let next = *l & 1;
            *l = (*l >> 1) | (carry << 31);
            carry = next;
        }
        BigInt {
            negative: self.negative,
            limbs,
        }
        .normalized()
    }
    fn to_f64(&self) -> f64 {
        let m = self
            .limbs
            .iter()
            .rev()
            .fold(0.0, |m, &l| m * 4_294_967_296.0 + f64::from(l));
        if self.negative { -m } else { m }
    }
    fn to_big(&self) -> BigInt {
        self.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn big_arithmetic_matches_i128() {
        // Against i128 where both fit, over signs and carries.
        let xs: [i128; 9] = [0, 1, -1, 7, -12345, 1 << 40, -(1 << 62) + 3, (1 << 63) - 1, -(1 << 50)];
        for &a in &xs {
            for &b in &xs {
                let (ba, bb) = (BigInt::from_i128(a), BigInt::from_i128(b));
                assert_eq!(Int::add(&ba, &bb).unwrap().to_i128(), Some(a + b), "{a} + {b}");
                assert_eq!(Int::mul(&ba, &bb).unwrap().to_i128(), Some(a * b), "{a} * {b}");
            }
            if a % 2 == 0 {
                assert_eq!(BigInt::from_i128(a).half().to_i128(), Some(a / 2));
            }
            // The i128 bit tricks against plain remainder and division.
            for v in [a, a.wrapping_neg(), a.wrapping_mul(3), a.wrapping_mul(2) - 2] {
                assert_eq!(Int::is_even(&v), v % 2 == 0, "{v} even");
                if v % 2 == 0 {
                    assert_eq!(Int::half(&v), v / 2, "{v} / 2");
                }
            }
        }
        // Past i128: (2^100)^2 = 2^200, minus itself is zero, not -0.
        let p = BigInt::from_i128(1 << 100);
        let sq = Int::mul(&p, &p).unwrap();
        assert_eq!(sq.parts().1.len(), 7);
        assert_eq!(sq.to_i128(), None);
        let neg = Int::mul(&sq, &BigInt::from_i128(-1)).unwrap();
        assert_eq!(Int::add(&sq, &neg).unwrap(), BigInt::zero());
        assert_eq!((sq.to_f64() / 2f64.powi(200) - 1.0).abs(), 0.0);
    }
}
