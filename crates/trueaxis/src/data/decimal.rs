//! Numbers written with a fixed count of decimals, fast: the text of `format!("{v:.n$}")` for the
//! rows of large tables (prediction tables, correction tables), where the standard formatting would
//! take most of the time.

/// Appends `v` with `decimals` digits after the point, the same text as `format!("{v:.decimals$}")`
/// (the exact binary value rounded half to even) at a fraction of its cost: `v * 10^decimals`
/// rounded to an integer is that rounding whenever the product (off by at most 1.1e-7 below 1e9)
/// is not within 1e-6 of a half; near a half, and for larger values, the standard formatting is
/// used. Tables of millions of rows spend most of their time here otherwise.
pub(crate) fn push_fixed(out: &mut String, v: f64, decimals: usize) {
    use std::fmt::Write;
    const POWERS: [f64; 7] = [1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6];
    let scaled = v * POWERS[decimals.min(6)];
    let rounded = scaled.round();
    // a value that is not finite, or beyond 1e9 scaled, goes to the standard formatting too
    let within = rounded.abs() < 1e9;
    if decimals > 6 || !within || (scaled - rounded).abs() > 0.5 - 1e-6 {
        let _ = write!(out, "{v:.decimals$}");
        return;
    }
    let n = rounded.abs() as u64;
    let unit = 10u64.pow(decimals as u32);
    let sign = if v.is_sign_negative() { "-" } else { "" };
    let _ = match decimals {
        0 => write!(out, "{sign}{n}"),
        _ => write!(out, "{sign}{}.{:0decimals$}", n / unit, n % unit),
    };
}
