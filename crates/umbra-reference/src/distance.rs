//! The exact Euclidean distance transform (Felzenszwalb and Huttenlocher 2012): for every pixel,
//! the distance to the nearest seed pixel, in O(pixels) by two passes of 1D lower envelopes of
//! parabolas.

/// Squared distance standing for "no seed on this line yet".
const FAR: f64 = 1e20;

/// Distance (in pixels, centre to centre) from each pixel to the nearest pixel with
/// `seed[i] == true`; every entry is infinite when there is no seed.
pub fn distance_to_seeds(width: usize, height: usize, seed: &[bool]) -> Vec<f32> {
    let mut d: Vec<f64> = seed.iter().map(|&s| if s { 0.0 } else { FAR }).collect();
    let mut line = vec![0.0; width.max(height)];
    let mut out = vec![0.0; width.max(height)];
    for x in 0..width {
        for y in 0..height {
            line[y] = d[y * width + x];
        }
        lower_envelope(&line[..height], &mut out[..height]);
        for y in 0..height {
            d[y * width + x] = out[y];
        }
    }
    for y in 0..height {
        let row = &mut d[y * width..(y + 1) * width];
        line[..width].copy_from_slice(row);
        lower_envelope(&line[..width], &mut out[..width]);
        row.copy_from_slice(&out[..width]);
    }
    d.into_iter().map(|v| if v >= FAR { f32::INFINITY } else { v.sqrt() as f32 }).collect()
}

/// `out[q] = min_p (q - p)² + f[p]`, the 1D squared distance transform.
fn lower_envelope(f: &[f64], out: &mut [f64]) {
    let n = f.len();
    if n == 0 {
        return;
    }
    // Parabola apexes and the boundaries between them.
    let mut v = vec![0usize; n];
    let mut z = vec![0.0f64; n + 1];
    let mut k = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in 1..n {
        let mut s;
        loop {
            let p = v[k];
            s = ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q as f64 - p as f64));
            // z[0] is -inf, so this stops at k = 0 at the latest.
            if s <= z[k] {
                k -= 1;
            } else {
                break;
            }
        }
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    let mut k = 0;
    for (q, o) in out.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        *o = (q as f64 - p as f64).powi(2) + f[p];
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn brute(width: usize, height: usize, seed: &[bool]) -> Vec<f32> {
        (0..width * height)
            .map(|i| {
                let (x, y) = ((i % width) as f32, (i / width) as f32);
                (0..width * height)
                    .filter(|&j| seed[j])
                    .map(|j| ((j % width) as f32 - x).hypot((j / width) as f32 - y))
                    .fold(f32::INFINITY, f32::min)
            })
            .collect()
    }

    proptest! {
        #[test]
        fn matches_brute_force(width in 1usize..12, height in 1usize..12, bits in proptest::collection::vec(0u8..10, 144)) {
            let seed: Vec<bool> = bits[..width * height].iter().map(|&b| b == 0).collect();
            let fast = distance_to_seeds(width, height, &seed);
            let slow = brute(width, height, &seed);
            for (a, b) in fast.iter().zip(&slow) {
                prop_assert!((a == b) || (a - b).abs() < 1e-4, "{a} vs {b}");
            }
        }
    }
}
