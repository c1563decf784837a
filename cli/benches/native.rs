//! Plain Rust versions of the interpreter benchmark programs (`tests/perf/programs`):
//! the floor a script could reach if it were compiled to native code.

use std::hint::black_box;

/// `arith.gbas`: returns (acc, x).
pub fn arith(iterations: i64) -> (i64, f64) {
    let mut acc: i64 = 0;
    let mut x: f64 = 0.0;
    for i in 1..=black_box(iterations) {
        acc = (acc + i * 7) % 1_000_003;
        x = x * 0.5 + (i % 10) as f64;
    }
    (acc, x)
}

/// `bins.gbas`: returns (acc, mean).
pub fn bins(repetitions: i64) -> (i64, f64) {
    const NBINS: usize = 50;
    let mut sum = [0.0f64; NBINS];
    let mut count = [0i64; NBINS];
    let mut avg = [0.0f64; NBINS];
    let mut deriv = [0.0f64; NBINS];
    let mut mean = 0.0;
    let mut acc: i64 = 0;
    for _ in 0..black_box(repetitions) {
        sum.fill(0.0);
        count.fill(0);
        for k in 0..400i64 {
            let z = (k % 50) as f64 + 0.25;
            let bin = z as usize;
            let mut temp = 20.0 - 0.05 * z;
            if z > 10.0 && z < 15.0 {
                temp -= z - 10.0;
            } else if z >= 15.0 {
                temp -= 5.0;
            }
            sum[bin] += temp;
            count[bin] += 1;
        }
        for bin in 0..NBINS {
            if count[bin] > 0 {
                avg[bin] = sum[bin] / count[bin] as f64;
            }
        }
        mean = 0.0;
        for bin in 1..NBINS {
            deriv[bin] = (avg[bin] - avg[bin - 1]).abs();
            mean += deriv[bin];
        }
        mean /= (NBINS - 1) as f64;
        let (mut upper, mut lower) = (-1i64, -1i64);
        for (bin, value) in deriv.iter().enumerate().skip(1) {
            if *value > mean {
                if upper < 0 {
                    upper = bin as i64;
                }
                lower = bin as i64;
            }
        }
        acc += upper + lower;
        black_box(&deriv);
    }
    (acc, mean)
}

/// `states.gbas`: returns (state, visits, turns).
pub fn states(iterations: i64) -> (i64, i64, i64) {
    let (mut state, mut visits, mut turns) = (0i64, 0i64, 0i64);
    for i in 1..=black_box(iterations) {
        match state {
            0 => state = if i % 3 == 0 { 1 } else { 2 },
            1 => {
                visits += 1;
                if i % 5 == 0 {
                    state = 3;
                }
            }
            2 => state = if i % 7 < 3 { 0 } else { 3 },
            _ => {
                turns += 1;
                state = (turns % 4) / 2;
            }
        }
    }
    (state, visits, turns)
}

/// `tight.gbas`: returns s.
pub fn tight(iterations: i64) -> i64 {
    let mut s: i64 = 0;
    for i in 1..=black_box(iterations) {
        s += (i * i) % 7;
    }
    s
}
