//! Integer number theory for the samplers whose point counts are powers or whose strata are
//! indexed by primes: integer roots, primality, primes by sieve and polynomials over the
//! prime field `Z/p`.
//!
//! Jittered, multi-jittered and multi-stage N-rooks sampling need a count to be a perfect
//! power (`k^d`, `m^2`, `n^k`), orthogonal arrays a prime power `p^t` and a field to evaluate
//! polynomials in, and the Halton bases are the first primes.

/// The largest `r` with `r^t <= n` (`t >= 1`; 0 for `n = 0`).
pub(super) fn integer_root(n: u64, t: u32) -> u64 {
    debug_assert!(t >= 1);
    if t == 1 || n <= 1 {
        return n;
    }
    let within = |r: u64| r.checked_pow(t).is_some_and(|power| power <= n);
    // The floating-point root is within a few units; correct it both ways. For t >= 2 the
    // root is at most 2^32, so r + 1 cannot overflow.
    let mut r = (n as f64).powf(1.0 / f64::from(t)) as u64;
    while r > 0 && !within(r) {
        r -= 1;
    }
    while within(r + 1) {
        r += 1;
    }
    r
}

/// The prime `p` with `p^t = n`, if there is one (`t >= 1`).
pub(super) fn prime_root(n: u64, t: u32) -> Option<u64> {
    let root = integer_root(n, t);
    (is_prime(root) && root.checked_pow(t) == Some(n)).then_some(root)
}

/// The largest `t` with `p^t` in a `u64` (`p >= 2`).
pub(super) fn max_exponent(p: u64) -> u32 {
    let mut t = 0;
    let mut power = 1u64;
    while let Some(next) = power.checked_mul(p) {
        power = next;
        t += 1;
    }
    t
}

/// `a * b mod m` without overflow.
fn mul_mod(a: u64, b: u64, m: u64) -> u64 {
    (u128::from(a) * u128::from(b) % u128::from(m)) as u64
}

/// `base^exp mod m` by squaring.
fn pow_mod(mut base: u64, mut exp: u64, m: u64) -> u64 {
    let mut result = 1 % m;
    base %= m;
    while exp > 0 {
        if exp & 1 == 1 {
            result = mul_mod(result, base, m);
        }
        base = mul_mod(base, base, m);
        exp >>= 1;
    }
    result
}

/// Deterministic Miller-Rabin: the first twelve primes as bases decide every `u64`
/// (Jaeschke 1993; Sorenson & Webster 2015).
pub(super) fn is_prime(n: u64) -> bool {
    const BASES: [u64; 12] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37];
    if n < 2 {
        return false;
    }
    for &b in &BASES {
        if n.is_multiple_of(b) {
            return n == b;
        }
    }
    let shift = (n - 1).trailing_zeros();
    let odd = (n - 1) >> shift;
    BASES.iter().all(|&a| {
        let mut x = pow_mod(a, odd, n);
        if x == 1 || x == n - 1 {
            return true;
        }
        for _ in 1..shift {
            x = mul_mod(x, x, n);
            if x == n - 1 {
                return true;
            }
        }
        false
    })
}

/// The smallest prime `>= n`, if one fits in a `u64`.
pub(super) fn next_prime(n: u64) -> Option<u64> {
    (n.max(2)..=u64::MAX).find(|&q| is_prime(q))
}

/// The largest prime `<= n`, if any.
pub(super) fn previous_prime(n: u64) -> Option<u64> {
    (2..=n).rev().find(|&q| is_prime(q))
}

/// A factor of the odd composite `n` other than 1 and `n`: Pollard's rho with Brent's cycle
/// detection, the differences multiplied together for a gcd every 64 steps (Brent 1980),
/// about `n^(1/4)` steps, where trial division takes up to `n^(1/2)`.
fn rho_factor(n: u64) -> u64 {
    const BATCH: u64 = 64;
    for c in 1..n {
        let step =
            |x: u64| ((u128::from(x) * u128::from(x) + u128::from(c)) % u128::from(n)) as u64;
        let (mut x, mut y, mut saved) = (2, 2, 2);
        let (mut product, mut factor, mut length) = (1, 1, 1);
        while factor == 1 {
            x = y;
            for _ in 0..length {
                y = step(y);
            }
            let mut done = 0;
            while done < length && factor == 1 {
                saved = y;
                for _ in 0..BATCH.min(length - done) {
                    y = step(y);
                    product = mul_mod(product, x.abs_diff(y), n);
                }
                factor = gcd(product, n);
                done += BATCH;
            }
            length *= 2;
        }
        if factor == n {
            // The batch overshot: retrace it one step at a time.
            loop {
                saved = step(saved);
                factor = gcd(x.abs_diff(saved), n);
                if factor > 1 {
                    break;
                }
            }
        }
        if factor != n {
            return factor;
        }
    }
    unreachable!("every odd composite has a rho cycle for some c")
}

fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The prime factors of `n >= 1`, with multiplicity, in no particular order.
fn prime_factors(mut n: u64) -> Vec<u64> {
    let mut factors = Vec::new();
    for p in [2, 3, 5, 7, 11, 13] {
        while n.is_multiple_of(p) {
            factors.push(p);
            n /= p;
        }
    }
    let mut pending = vec![n];
    while let Some(m) = pending.pop() {
        if m == 1 {
            continue;
        }
        if is_prime(m) {
            factors.push(m);
        } else {
            let d = rho_factor(m);
            pending.extend([d, m / d]);
        }
    }
    factors
}

/// The largest divisor of `n >= 1` that is at most `sqrt(n)`: the side of the squarest
/// `m x (n / m)` grid. From the prime factors, so a prime near `2^53` is found as fast as a
/// power of two (walking down from the root took a second there).
pub(super) fn squarest_divisor(n: u64) -> u64 {
    let root = integer_root(n, 2);
    let mut factors = prime_factors(n);
    factors.sort_unstable();
    let mut divisors = vec![1u64];
    for group in factors.chunk_by(|a, b| a == b) {
        let known = divisors.len();
        let mut power = 1u64;
        for &p in group {
            power *= p;
            for i in 0..known {
                if let Some(d) = divisors[i].checked_mul(power).filter(|&d| d <= root) {
                    divisors.push(d);
                }
            }
        }
    }
    divisors.into_iter().max().unwrap_or(1)
}

/// Every prime below `bound`, in increasing order, by the sieve of Eratosthenes.
pub(super) fn primes_below(bound: usize) -> Vec<u64> {
    let mut composite = vec![false; bound];
    let mut primes = Vec::new();
    for n in 2..bound {
        if composite[n] {
            continue;
        }
        primes.push(n as u64);
        for multiple in (n.saturating_mul(n)..bound).step_by(n) {
            composite[multiple] = true;
        }
    }
    primes
}

/// The polynomial `c_0 + c_1 x + ... + c_(t-1) x^(t-1)` over the field `Z/p` at `x = at`,
/// by Horner's rule (`coefficients` lowest first, each below `p`; `at < p`).
#[inline]
pub(super) fn polynomial_mod(coefficients: &[u64], at: u64, p: u64) -> u64 {
    let (at, p) = (u128::from(at), u128::from(p));
    coefficients
        .iter()
        .rev()
        .fold(0u128, |acc, &c| (acc * at + u128::from(c)) % p) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integer_root_is_exact_at_and_around_powers() {
        assert_eq!(integer_root(0, 3), 0);
        assert_eq!(integer_root(1, 3), 1);
        assert_eq!(integer_root(26, 3), 2);
        assert_eq!(integer_root(27, 3), 3);
        assert_eq!(integer_root(48, 2), 6);
        assert_eq!(integer_root(49, 2), 7);
        assert_eq!(integer_root(63, 2), 7);
        assert_eq!(integer_root(64, 2), 8);
        assert_eq!(integer_root(65, 2), 8);
        assert_eq!(integer_root(124, 3), 4);
        assert_eq!(integer_root(125, 3), 5);
        assert_eq!(integer_root(1 << 53, 53), 2);
        assert_eq!(integer_root(u64::MAX, 1), u64::MAX);
        assert_eq!(integer_root(u64::MAX, 2), u64::from(u32::MAX));
        assert_eq!(integer_root(u64::MAX, 64), 1);
        // Jittered sampling asks for roots of order up to u32::MAX (dimensions beyond it).
        assert_eq!(integer_root(u64::MAX, u32::MAX), 1);
        assert_eq!(max_exponent(2), 63);
        assert_eq!(max_exponent(3), 40);
    }

    #[test]
    fn integer_root_matches_a_search_over_small_powers() {
        for t in 2..=6u32 {
            for n in 0..5000u64 {
                let root = (0..=n).take_while(|r| r.pow(t) <= n).last().unwrap_or(0);
                assert_eq!(integer_root(n, t), root, "{n}^(1/{t})");
            }
        }
    }

    #[test]
    fn prime_roots_are_found_only_for_prime_powers() {
        assert_eq!(prime_root(49, 2), Some(7));
        assert_eq!(prime_root(125, 3), Some(5));
        assert_eq!(prime_root(13, 1), Some(13));
        assert_eq!(prime_root(64, 3), None); // 4^3: 4 is not prime
        assert_eq!(prime_root(50, 2), None);
        assert_eq!(prime_root(1, 2), None);
        assert_eq!(prime_root(0, 2), None);
        let p = 4_294_967_291u64; // the largest prime below 2^32
        assert_eq!(prime_root(p * p, 2), Some(p));
    }

    #[test]
    fn primality_matches_trial_division_and_known_large_primes() {
        let trial = |n: u64| {
            n >= 2
                && (2..n)
                    .take_while(|d| d * d <= n)
                    .all(|d| !n.is_multiple_of(d))
        };
        for n in 0..5000 {
            assert_eq!(is_prime(n), trial(n), "{n}");
        }
        assert!(is_prime(4_294_967_291)); // largest prime below 2^32
        assert!(is_prime(18_446_744_073_709_551_557)); // largest prime below 2^64
        assert!(!is_prime(3_215_031_751)); // strong pseudoprime to bases 2, 3, 5, 7
        assert!(!is_prime(u64::MAX));
        assert_eq!(next_prime(18_446_744_073_709_551_558), None);
        assert_eq!(previous_prime(1), None);
    }

    /// The squarest divisor by walking down from the root: the definition.
    fn squarest_by_search(n: u64) -> u64 {
        (1..=integer_root(n, 2))
            .rev()
            .find(|&m| n.is_multiple_of(m))
            .unwrap()
    }

    #[test]
    fn squarest_divisors_match_a_search_down_from_the_root() {
        for n in 1..3000 {
            assert_eq!(squarest_divisor(n), squarest_by_search(n), "n = {n}");
        }
        // Random counts up to 2^24, then a prime, a prime square and semiprimes near 2^53 and
        // a product of many primes; primes and divisors from sympy (`isprime`, `prevprime`,
        // `max(d for d in divisors(n) if d * d <= n)`).
        let mut state = 7u64;
        for _ in 0..40 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let n = (state >> 40) + 1;
            assert_eq!(squarest_divisor(n), squarest_by_search(n), "n = {n}");
        }
        for (n, m) in [
            (1 << 53, 1 << 26),
            ((1 << 53) - 111, 1), // the largest prime below 2^53
            (94_906_249 * 94_906_249, 94_906_249), // a prime squared, near 2^53
            (67_108_859 * 134_217_689, 67_108_859), // primes near 2^26 and 2^27
            (3 * 4_503_599_627_370_449, 3), // 3 times a prime near 2^52
            (614_889_782_588_491_410, 783_152_070), // the primes up to 47
        ] {
            assert!(factors_multiply_out(n), "n = {n}");
            assert_eq!(squarest_divisor(n), m, "n = {n}");
        }
    }

    fn factors_multiply_out(n: u64) -> bool {
        let factors = prime_factors(n);
        factors.iter().all(|&p| is_prime(p)) && factors.iter().product::<u64>() == n
    }

    #[test]
    fn sieve_finds_the_primes_miller_rabin_finds() {
        let sieved = primes_below(20_000);
        let tested: Vec<u64> = (0..20_000).filter(|&n| is_prime(n)).collect();
        assert_eq!(sieved, tested);
        assert!(primes_below(2).is_empty());
        // The 10,000th prime, the last Halton base.
        assert_eq!(primes_below(104_730).len(), 10_000);
        assert_eq!(primes_below(104_730).last(), Some(&104_729));
    }

    #[test]
    fn polynomials_mod_p_follow_horner() {
        // 3 + 2x + x^2 at x = 4 is 27 = 6 mod 7.
        assert_eq!(polynomial_mod(&[3, 2, 1], 4, 7), 6);
        assert_eq!(polynomial_mod(&[5], 3, 7), 5);
        // No overflow near 2^64: (p - 1) + (p - 1) x at x = p - 1 is (p - 1) p = 0 mod p.
        let p = 18_446_744_073_709_551_557u64;
        assert_eq!(polynomial_mod(&[p - 1, p - 1], p - 1, p), 0);
    }
}
