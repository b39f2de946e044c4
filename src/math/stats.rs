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

/// The `k`-th smallest of `v` in [`f32::total_cmp`]'s order (0: the least), the value
/// `v.select_nth_unstable_by(k, f32::total_cmp)` gives; `None` when `k >= v.len()`. Reorders
/// `v`. A quickselect of its own (median-of-three pivot, three-way partition): the standard
/// library's selection (median of medians and its partition, insertion sort and heap sort)
/// was about 4 KB raw of the `.wasm`, for one setup-time quartile.
pub fn nth_smallest(v: &mut [f32], k: usize) -> Option<f32> {
    if k >= v.len() {
        return None;
    }
    // v[lo..hi] holds the k-th smallest; the parts outside are on their side of it.
    let (mut lo, mut hi) = (0, v.len());
    loop {
        let (a, b, c) = (v[lo], v[lo + (hi - lo) / 2], v[hi - 1]);
        let pivot = if a.total_cmp(&b).is_lt() == b.total_cmp(&c).is_lt() {
            b
        } else if a.total_cmp(&b).is_lt() == a.total_cmp(&c).is_lt() {
            c
        } else {
            a
        };
        // v[lo..lt] < pivot, v[lt..i] == pivot, v[gt..hi] > pivot.
        let (mut lt, mut i, mut gt) = (lo, lo, hi);
        while i < gt {
            match v[i].total_cmp(&pivot) {
                core::cmp::Ordering::Less => {
                    v.swap(lt, i);
                    lt += 1;
                    i += 1;
                }
                core::cmp::Ordering::Greater => {
                    gt -= 1;
                    v.swap(i, gt);
                }
                core::cmp::Ordering::Equal => i += 1,
            }
        }
        // The pivot is one of v[lo..hi], so lt < gt: the range shrinks every round.
        if k < lt {
            hi = lt;
        } else if k >= gt {
            lo = gt;
        } else {
            return Some(pivot);
        }
    }
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

#[cfg(test)]
mod tests {
    use super::nth_smallest;

    #[test]
    fn nth_smallest_is_the_standard_selection() {
        let mut seed = 12345u32;
        let mut next = || {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            seed >> 8
        };
        for n in [1usize, 2, 3, 7, 8, 33, 100, 1000] {
            for round in 0..20 {
                let v: Vec<f32> = (0..n)
                    .map(|_| match (round, next() % 10) {
                        // Few distinct values: many duplicates.
                        (0..=4, r) => r as f32 * 0.5,
                        (_, 0) => -0.0,
                        (_, 1) => f32::NAN,
                        _ => (next() % 20_000) as f32 * 1e-3 - 10.0,
                    })
                    .collect();
                for k in [0, n / 4, n / 2, n * 3 / 4, n - 1] {
                    let mut ours = v.clone();
                    let mut std = v.clone();
                    let want = *std.select_nth_unstable_by(k, f32::total_cmp).1;
                    let got = nth_smallest(&mut ours, k).unwrap();
                    assert_eq!(got.to_bits(), want.to_bits(), "n {n} round {round} k {k}");
                }
            }
        }
        assert_eq!(nth_smallest(&mut [], 0), None);
        assert_eq!(nth_smallest(&mut [1.0, 2.0], 2), None);
        // Sorted and reversed input (a first-element pivot's worst case).
        let mut up: Vec<f32> = (0..500).map(|i| i as f32).collect();
        assert_eq!(nth_smallest(&mut up, 375), Some(375.0));
        let mut down: Vec<f32> = (0..500).rev().map(|i| i as f32).collect();
        assert_eq!(nth_smallest(&mut down, 10), Some(10.0));
    }
}
