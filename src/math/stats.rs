//! Robust statistics of calibration samples: a mean that ignores outliers, over samples kept
//! sorted as they arrive (no sort per frame, no allocation).

/// Samples further than this fraction from the median are outliers.
pub const OUTLIER_FRACTION: f32 = 0.2;

/// Mean of the samples within [`OUTLIER_FRACTION`] of their median; `None` for no samples.
/// `scratch` must be at least as long as `samples`. Sorts in place: no allocation.
#[must_use]
pub fn robust_mean(samples: &[f32], scratch: &mut [f32]) -> Option<f32> {
    let n = samples.len().min(scratch.len());
    let sorted = &mut scratch[..n];
    sorted.copy_from_slice(&samples[..n]);
    sorted.sort_unstable_by(f32::total_cmp);
    robust_mean_sorted(sorted)
}

/// Inserts `x` into the ascending `buf[..count]` (which becomes `buf[..count + 1]`); does
/// nothing when `buf` is full. The calibrations collect their samples so, one per frame, and
/// need no sort (O(n) a sample; and no copy of the standard library's sort in the `.wasm`).
pub fn insert_sorted(buf: &mut [f32], count: usize, x: f32) {
    if count >= buf.len() {
        return;
    }
    let mut k = count;
    while k > 0 && buf[k - 1].total_cmp(&x).is_gt() {
        buf[k] = buf[k - 1];
        k -= 1;
    }
    buf[k] = x;
}

/// [`robust_mean`] of samples already in ascending order (as [`insert_sorted`] keeps them).
#[must_use]
pub fn robust_mean_sorted(sorted: &[f32]) -> Option<f32> {
    let n = sorted.len();
    if n == 0 {
        return None;
    }
    let median = if n % 2 == 1 {
        sorted[n / 2]
    } else {
        0.5 * (sorted[n / 2 - 1] + sorted[n / 2])
    };
    let (sum, kept) = sorted
        .iter()
        .filter(|&&x| (x - median).abs() <= OUTLIER_FRACTION * median)
        .fold((0.0f32, 0u32), |(s, k), &x| (s + x, k + 1));
    // The median itself is always kept when it is a sample; with an even count the two
    // middle samples may both be outliers of their own mean: fall back to the median.
    Some(if kept > 0 { sum / kept as f32 } else { median })
}
