//! The oracle's byte reader and the decoding of scene parameters and nudged values.

use super::*;

/// Reads bytes front to back; past the end every read is zero, so every input decodes.
pub(super) struct Bytes<'a> {
    pub(super) data: &'a [u8],
    pub(super) pos: usize,
}

impl<'a> Bytes<'a> {
    pub(super) fn new(data: &'a [u8]) -> Self {
        Bytes { data, pos: 0 }
    }
    pub(super) fn u8(&mut self) -> u8 {
        let b = self.data.get(self.pos).copied().unwrap_or(0);
        self.pos += 1;
        b
    }
    pub(super) fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }
    pub(super) fn u32(&mut self) -> u32 {
        u32::from_le_bytes([self.u8(), self.u8(), self.u8(), self.u8()])
    }
    /// A fraction in [0, 1], both ends included.
    pub(super) fn frac16(&mut self) -> f64 {
        self.u16() as f64 / 65535.0
    }
    /// A fraction in [0, 1), fine-grained.
    pub(super) fn frac32(&mut self) -> f64 {
        self.u32() as f64 / 4_294_967_296.0
    }
    /// A fraction in (0, 1), both ends excluded.
    pub(super) fn open16(&mut self) -> f64 {
        (self.u16() as f64 + 1.0) / 65537.0
    }
}

/// Small signed offsets, 0 first so that missing bytes mean "no nudge".
pub(super) const NUDGE: [i32; 9] = [0, 1, -1, 2, -2, 3, -3, 4, -4];

pub(super) fn next_up(x: f64) -> f64 {
    if x.is_nan() || x == f64::INFINITY {
        return x;
    }
    if x == 0.0 {
        return f64::from_bits(1);
    }
    let b = x.to_bits();
    f64::from_bits(if x > 0.0 { b + 1 } else { b - 1 })
}

pub(super) fn next_down(x: f64) -> f64 {
    -next_up(-x)
}

/// `x` moved by `n` ulps.
pub(super) fn nudge(mut x: f64, n: i32) -> f64 {
    for _ in 0..n.unsigned_abs() {
        x = if n > 0 { next_up(x) } else { next_down(x) };
    }
    x
}

pub(super) fn hp(x: f64) -> Float {
    Float::with_val(ORACLE_BITS, x)
}

pub(super) fn pi() -> Float {
    Float::with_val(ORACLE_BITS, Constant::Pi)
}

/// The unit vector at angle `theta` (computed at [`ORACLE_BITS`], then rounded).
pub(super) fn unit(theta: &Float) -> Vec2<Float> {
    let (s, c) = theta.clone().sin_cos(Float::new(ORACLE_BITS));
    Vec2::new(c, s)
}

pub(super) fn angle_of(v: &Vec2<Float>) -> Float {
    v.y.clone().atan2(&v.x)
}

pub(super) fn round(p: &Vec2<Float>) -> Vec2<f64> {
    Vec2::new(p.x.to_f64(), p.y.to_f64())
}

pub(super) fn lift(p: &Vec2<f64>) -> Vec2<Float> {
    Vec2::<Float>::from_f64(ORACLE_BITS, p.x, p.y)
}

/// The largest f64 gap strictly below w∞.
pub(super) fn w_max() -> f64 {
    let wi = Geometry::<Float>::w_inf(ORACLE_BITS);
    let mut w = wi.to_f64();
    while hp(w) >= wi {
        w = next_down(w);
    }
    w
}

/// The smallest f64 gap strictly above w∞.
pub(super) fn w_min_open() -> f64 {
    let wi = Geometry::<Float>::w_inf(ORACLE_BITS);
    let mut w = wi.to_f64();
    while hp(w) <= wi {
        w = next_up(w);
    }
    w
}

/// w from a mode byte and 32 bits: uniform in (0, w∞), uniform in (w∞, 2) (an infinite
/// horizon: flights along the corridors cross many traps), a power 2⁻ᵉ (e = 2..=40), or within
/// ~2⁻¹⁴ (relative) of w∞ below it.
pub(super) fn decode_w(r: &mut Bytes) -> f64 {
    let mode = r.u8() % 4;
    let n = r.u32();
    let wm = w_max();
    match mode {
        0 => wm * ((n as f64 + 1.0) / 4_294_967_297.0),
        1 => {
            let lo = w_min_open();
            lo + (2.0 - lo) * (n as f64 / 4_294_967_296.0)
        }
        2 => (-((2 + n % 39) as f64)).exp2(),
        _ => wm * (1.0 - (n >> 18) as f64 * (-32f64).exp2()),
    }
}

/// r from a mode byte and 32 bits: uniform in (0, ½), a power 2⁻ᵉ (e = 2..=40), or ½ − 2⁻ᵏ
/// (k = 2..=53, exact; ½ − 2⁻⁵³ is the largest double below ½).
pub(super) fn decode_r(r: &mut Bytes) -> f64 {
    let mode = r.u8() % 4;
    let n = r.u32();
    match mode {
        0 | 1 => 0.5 * ((n as f64 + 1.0) / 4_294_967_297.0),
        2 => (-((2 + n % 39) as f64)).exp2(),
        _ => 0.5 - (-((2 + n % 52) as f64)).exp2(),
    }
}
