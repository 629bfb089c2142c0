//! Multiple importance sampling (Veach and Guibas 1995): the power heuristic (β = 2)
//! that weighs a light sample against a BSDF sample of the same path, as Mitsuba's path
//! integrator does.

/// Weight of a sample drawn with density `a` when the other strategy would have drawn
/// it with density `b`: `a² / (a² + b²)`. `w(a, b) + w(b, a) = 1` whenever either is
/// positive; a density that overflows wins outright, and two zeros weigh 0.
pub(crate) fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2.is_infinite() {
        return if b2.is_infinite() { 0.5 } else { 1.0 };
    }
    if b2.is_infinite() {
        return 0.0;
    }
    let s = a2 + b2;
    if s > 0.0 {
        a2 / s
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn weights_of_the_two_strategies_sum_to_one() {
        for (a, b) in
            [(1.0, 1.0), (0.3, 7.0), (1e-20, 3.0), (1e30, 1e30), (0.0, 2.0), (f32::INFINITY, 1.0), (5e19, 5e19)]
        {
            let (wa, wb) = (power_heuristic(a, b), power_heuristic(b, a));
            assert!((wa + wb - 1.0).abs() < 1e-6, "{a}, {b}: {wa} + {wb}");
            assert!((0.0..=1.0).contains(&wa));
        }
        assert_eq!(power_heuristic(1.0, 1.0), 0.5);
        assert_eq!(power_heuristic(0.0, 0.0), 0.0);
        assert!((power_heuristic(2.0, 1.0) - 0.8).abs() < 1e-7);
    }
}
