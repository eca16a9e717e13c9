#pragma once
/// @file Alg. 5 (§5.6.2, digest §3.8.1): the time of the next fracture along a solution that is
/// affine in time, by bracketing with doubling steps and bisecting to the time tolerance.

#include <algorithm>

namespace crackle::fracture {

/// From `t0`, steps of `last_step` (at least `dt_min`), doubling, until `over(t)` says some
/// candidate is over its threshold or `horizon` is reached; then `narrow(t_hi)` lets the caller
/// keep only the candidates over at t_hi (the first crossing is among them: each ratio is convex
/// in time), and bisection closes in on the crossing to `dt_min`. Returns the time to advance
/// to: just past the first crossing, or the horizon when none comes before it; `last_step`
/// becomes the step that found it.
template <class Over, class Narrow>
double next_crossing(double t0, double horizon, double dt_min, double& last_step, Over&& over, Narrow&& narrow) {
    double t_lo = t0, t_hi = t0, dt = std::max(last_step, dt_min);
    bool found = false;
    while (t_hi < horizon) {
        t_hi = std::min(t_lo + dt, horizon);
        if (over(t_hi)) {
            found = true;
            break;
        }
        t_lo = t_hi;
        dt *= 2.0;
    }
    if (found) {
        narrow(t_hi);
        while (t_hi - t_lo > dt_min) {
            const double mid = 0.5 * (t_lo + t_hi);
            (over(mid) ? t_hi : t_lo) = mid;
        }
        last_step = std::max(t_hi - t0, dt_min);
    }
    return t_hi;
}

} // namespace crackle::fracture
