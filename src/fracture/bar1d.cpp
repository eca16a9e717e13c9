#include "fracture/bar1d.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

namespace crackle::fracture::bar1d {

namespace {

/// Relative tolerance under which two tensions or two crossing times count as a tie.
constexpr double TIE_TOLERANCE = 1e-12;

void check_stiffness(const Stiffness& s) {
    CRACKLE_ASSERT(s.K_S > 0 && s.K_A > 0, "bar1d needs K_S > 0 and K_A > 0, got " << s.K_S << ", " << s.K_A);
}

/// Solves the symmetric tridiagonal system with diagonal `diag` (#N) and off-diagonal `off`
/// (#N − 1) by the Thomas algorithm (no pivoting: the matrix is diagonally dominant).
VecX solve_tridiagonal(VecX diag, const VecX& off, VecX rhs) {
    const Eigen::Index n = diag.size();
    const auto check_pivot = [&](Eigen::Index i) {
        if (!(diag[i] > 0) || !std::isfinite(diag[i])) {
            std::ostringstream os;
            os << "bar1d: tridiagonal solve met pivot " << diag[i] << " at node " << i << " of " << n
               << " (K_A must be positive and every sub-segment must have positive size)";
            throw NumericError(os.str());
        }
    };
    // === Forward elimination
    check_pivot(0);
    for (Eigen::Index i = 1; i < n; ++i) {
        const double w = off[i - 1] / diag[i - 1];
        diag[i] -= w * off[i - 1];
        rhs[i] -= w * rhs[i - 1];
        check_pivot(i);
    }
    // === Back substitution
    VecX x(n);
    x[n - 1] = rhs[n - 1] / diag[n - 1];
    for (Eigen::Index i = n - 2; i >= 0; --i)
        x[i] = (rhs[i] - off[i] * x[i + 1]) / diag[i];
    return x;
}

/// Index of the largest value among the intact springs, ties within TIE_TOLERANCE going to the
/// lowest index; #S when every spring is broken.
std::size_t most_stressed(const DiscreteBar& bar, const VecX& tensions) {
    std::size_t best = bar.num_springs();
    for (std::size_t j = 0; j < bar.num_springs(); ++j) {
        if (bar.broken[j]) continue;
        const double Tj = tensions[static_cast<Eigen::Index>(j)];
        if (best == bar.num_springs()) {
            best = j;
            continue;
        }
        const double Tbest = tensions[static_cast<Eigen::Index>(best)];
        if (Tj > Tbest + TIE_TOLERANCE * std::abs(Tbest)) best = j;
    }
    return best;
}

void validate(const SimulationOptions& o) {
    const std::string where = "bar1d::simulate";
    if (!(o.stiffness.K_S > 0) || !(o.stiffness.K_A > 0))
        throw InputError(where, "K_S and K_A must be positive", "set both stiffnesses > 0");
    if (o.segments < 1) throw InputError(where, "segments must be at least 1", "use segments >= 1");
    if (!(o.length > 0)) throw InputError(where, "length must be positive", "use length > 0");
    if (!(o.break_tension > 0)) throw InputError(where, "break_tension must be positive", "use T_b = K_S * eps_b > 0");
    if (!(o.duration >= 0) || !std::isfinite(o.duration))
        throw InputError(where, "duration must be finite and non-negative", "use duration >= 0");
    if (!std::isfinite(o.growth_rate) || !std::isfinite(o.shrinkage_rate) || !std::isfinite(o.rest_growth_rate))
        throw InputError(where, "growth, shrinkage and rest growth rates must be finite", "use finite rates");
    if (!(o.max_rest_length >= 0)) throw InputError(where, "max_rest_length must be >= 0", "use 0 to disable");
    if (!(1.0 + (o.rest_growth_rate - o.shrinkage_rate) * o.duration > 0))
        throw InputError(where, "rest lengths shrink to zero before the end of the run",
                         "reduce shrinkage_rate or duration so that (shrinkage - rest growth) * duration < 1");
}

/// Anchors and rest lengths at time t: a_i = X_i·(1 + g·t), h_j = m_j·(1 + (q − s)·t).
void set_time(DiscreteBar& bar, const SimulationOptions& o, double t) {
    for (std::size_t i = 0; i < bar.num_nodes(); ++i)
        bar.anchors[i] = bar.reference[i] * (1.0 + o.growth_rate * t);
    const double rest_factor = 1.0 + (o.rest_growth_rate - o.shrinkage_rate) * t;
    for (std::size_t j = 0; j < bar.num_springs(); ++j)
        bar.rest[j] = bar.size(j) * rest_factor;
}

/// The same bar with the time derivatives ȧ = g·X and ḣ = (q − s)·m in place of the anchors
/// and rest lengths: by linearity its equilibrium is ṗ and its tensions are Ṫ.
DiscreteBar rate_bar(const DiscreteBar& bar, const SimulationOptions& o) {
    DiscreteBar rates = bar;
    for (std::size_t i = 0; i < bar.num_nodes(); ++i)
        rates.anchors[i] = bar.reference[i] * o.growth_rate;
    for (std::size_t j = 0; j < bar.num_springs(); ++j)
        rates.rest[j] = bar.size(j) * (o.rest_growth_rate - o.shrinkage_rate);
    return rates;
}

} // namespace

// === Continuous model

ContinuousSolution solve_continuous(const Stiffness& stiffness, const Segment& segment, const Boundary& boundary) {
    check_stiffness(stiffness);
    CRACKLE_ASSERT(segment.l0 > 0, "bar1d: fragment length must be positive, got " << segment.l0);
    const double r = stiffness.r();
    const double rl = r * segment.l0;
    const double d = segment.mismatch();
    const double sh = std::sinh(rl);
    const double ch = std::cosh(rl);
    ContinuousSolution s{stiffness, segment, 0.0, 0.0};
    // Federl 2002, App. A.2 (digest §2.6.2 table, [R]), with p' = λ at a free end.
    switch (boundary.type) {
    case BoundaryType::FreeFree: // Eq. A.11
        s.C1 = -d / rl;
        s.C2 = d / rl * std::tanh(0.5 * rl);
        break;
    case BoundaryType::LeftFixed: // Eq. A.12
        s.C2 = boundary.Z_L - segment.a0;
        s.C1 = -(d + rl * s.C2 * sh) / (rl * ch);
        break;
    case BoundaryType::RightFixed: // Eqs. A.13–A.14
        s.C1 = -d / rl;
        s.C2 = (boundary.Z_R - segment.an + d / rl * sh) / ch;
        break;
    case BoundaryType::BothFixed: // Eqs. A.15–A.16
        s.C2 = boundary.Z_L - segment.a0;
        s.C1 = (boundary.Z_R - segment.an - s.C2 * ch) / sh;
        break;
    }
    if (!std::isfinite(s.C1) || !std::isfinite(s.C2)) {
        std::ostringstream os;
        os << "bar1d: continuous solution overflows for r*l0 = " << rl << " (C1 = " << s.C1 << ", C2 = " << s.C2
           << "); use a shorter fragment or the discrete model";
        throw NumericError(os.str());
    }
    return s;
}

double position(const ContinuousSolution& s, double x) {
    const Segment& g = s.segment;
    const double r = s.stiffness.r();
    // Eq. A.5: p(x) = (a_n − a₀)·x/l₀ + a₀ + C₁·sinh(r·x) + C₂·cosh(r·x)
    return (g.an - g.a0) * x / g.l0 + g.a0 + s.C1 * std::sinh(r * x) + s.C2 * std::cosh(r * x);
}

double slope(const ContinuousSolution& s, double x) {
    const Segment& g = s.segment;
    const double r = s.stiffness.r();
    return (g.an - g.a0) / g.l0 + r * (s.C1 * std::cosh(r * x) + s.C2 * std::sinh(r * x));
}

double tension(const ContinuousSolution& s, double x) {
    // T(x) = K_S·(p'(x) − λ)
    return s.stiffness.K_S * (slope(s, x) - s.segment.lambda);
}

TensionPeak max_tension(const ContinuousSolution& s) {
    const double l0 = s.segment.l0;
    TensionPeak best{0.0, tension(s, 0.0)};
    const auto consider = [&](double x) {
        const double T = tension(s, x);
        if (T > best.tension) best = {x, T};
    };
    // === Interior stationary point: p''(x) = r²·(C₁·sinh(r·x) + C₂·cosh(r·x)) = 0
    if (s.C1 != 0.0) {
        const double q = -s.C2 / s.C1; // tanh(r·x) = −C₂/C₁
        if (std::abs(q) < 1.0) {
            const double x = std::atanh(q) / s.stiffness.r();
            if (x > 0.0 && x < l0) consider(x);
        }
    }
    consider(l0);
    return best;
}

double tension_free(const Stiffness& stiffness, double l0, double d, double x) {
    check_stiffness(stiffness);
    const double r = stiffness.r();
    return stiffness.K_S * d / l0 * (1.0 - std::cosh(r * (x - 0.5 * l0)) / std::cosh(0.5 * r * l0));
}

double max_tension_free(const Stiffness& stiffness, double l0, double d) {
    check_stiffness(stiffness);
    // T_max = K_S·d/l₀·(1 − sech(r·l₀/2))
    return stiffness.K_S * d / l0 * (1.0 - 1.0 / std::cosh(0.5 * stiffness.r() * l0));
}

double break_time_free(const Stiffness& stiffness, double l0, double growth_rate, double break_tension) {
    check_stiffness(stiffness);
    CRACKLE_ASSERT(growth_rate > 0, "bar1d: break time needs a positive growth rate, got " << growth_rate);
    // t* = T_b / (K_S·g·(1 − sech(r·l₀/2)))
    return break_tension / (stiffness.K_S * growth_rate * (1.0 - 1.0 / std::cosh(0.5 * stiffness.r() * l0)));
}

// === Discrete model

DiscreteBar uniform_bar(const Stiffness& stiffness, int n, const Segment& segment) {
    check_stiffness(stiffness);
    CRACKLE_ASSERT(n >= 1, "bar1d: need at least one sub-segment, got " << n);
    CRACKLE_ASSERT(segment.l0 > 0, "bar1d: bar length must be positive, got " << segment.l0);
    const auto springs = static_cast<std::size_t>(n);
    const double h = segment.l0 / n;
    DiscreteBar bar;
    bar.stiffness = stiffness;
    bar.reference.resize(springs + 1);
    bar.anchors.resize(springs + 1);
    for (std::size_t i = 0; i <= springs; ++i) {
        // The last node sits exactly at l₀.
        const double X = i == springs ? segment.l0 : static_cast<double>(i) * h;
        bar.reference[i] = X;
        bar.anchors[i] = segment.a0 + (segment.an - segment.a0) * X / segment.l0;
    }
    bar.rest.assign(springs, segment.lambda * h);
    bar.broken.assign(springs, 0);
    return bar;
}

VecX equilibrium(const DiscreteBar& bar) {
    check_stiffness(bar.stiffness);
    const std::size_t N = bar.num_nodes();
    CRACKLE_ASSERT(N >= 2 && bar.anchors.size() == N && bar.broken.size() == N - 1 && bar.rest.size() == N - 1,
                   "bar1d: inconsistent bar (" << N << " nodes, " << bar.anchors.size() << " anchors, "
                                               << bar.rest.size() << " rest lengths, " << bar.broken.size()
                                               << " broken flags)");
    const auto n = static_cast<Eigen::Index>(N);
    VecX diag = VecX::Zero(n);
    VecX off = VecX::Zero(n - 1);
    VecX rhs = VecX::Zero(n);
    // === Assemble Eq. A.1 per sub-segment: energy ½·k·(p_{j+1} − p_j − h)² + Σ_ends ½·c·(p − a)²
    for (std::size_t j = 0; j + 1 < N; ++j) {
        const auto i = static_cast<Eigen::Index>(j);
        const double m = bar.size(j);
        // Anchor springs K_A·m/2 at both ends; they stay when the material spring breaks.
        const double c = 0.5 * bar.stiffness.K_A * m;
        diag[i] += c;
        diag[i + 1] += c;
        rhs[i] += c * bar.anchors[j];
        rhs[i + 1] += c * bar.anchors[j + 1];
        if (bar.broken[j]) continue;
        // Material spring K_S/m; its rest length h pushes the end nodes apart.
        const double k = bar.stiffness.K_S / m;
        diag[i] += k;
        diag[i + 1] += k;
        off[i] = -k;
        rhs[i] -= k * bar.rest[j];
        rhs[i + 1] += k * bar.rest[j];
    }
    return solve_tridiagonal(std::move(diag), off, std::move(rhs));
}

VecX spring_tensions(const DiscreteBar& bar, const VecX& p) {
    CRACKLE_ASSERT(static_cast<std::size_t>(p.size()) == bar.num_nodes(),
                   "bar1d: " << p.size() << " positions for " << bar.num_nodes() << " nodes");
    VecX T = VecX::Zero(static_cast<Eigen::Index>(bar.num_springs()));
    for (std::size_t j = 0; j < bar.num_springs(); ++j) {
        if (bar.broken[j]) continue;
        const auto i = static_cast<Eigen::Index>(j);
        // T_j = (K_S/m_j)·(p_{j+1} − p_j − h_j)
        T[i] = bar.stiffness.K_S / bar.size(j) * (p[i + 1] - p[i] - bar.rest[j]);
    }
    return T;
}

void break_spring(DiscreteBar& bar, std::size_t j) {
    CRACKLE_ASSERT(j < bar.num_springs(), "bar1d: spring " << j << " of " << bar.num_springs());
    bar.broken[j] = 1;
}

void subdivide(DiscreteBar& bar, std::size_t j) {
    CRACKLE_ASSERT(j < bar.num_springs(), "bar1d: spring " << j << " of " << bar.num_springs());
    CRACKLE_ASSERT(!bar.broken[j], "bar1d: only intact sub-segments are subdivided (spring " << j << ")");
    const auto at = static_cast<std::ptrdiff_t>(j) + 1;
    const double X_mid = bar.midpoint(j);
    const double a_mid = 0.5 * (bar.anchors[j] + bar.anchors[j + 1]);
    const double half_rest = 0.5 * bar.rest[j];
    bar.reference.insert(bar.reference.begin() + at, X_mid);
    bar.anchors.insert(bar.anchors.begin() + at, a_mid);
    bar.rest[j] = half_rest;
    bar.rest.insert(bar.rest.begin() + at, half_rest);
    bar.broken.insert(bar.broken.begin() + at, char{0});
}

// === Discrete fracture simulation

SimulationResult simulate(const SimulationOptions& o) {
    validate(o);
    SimulationResult result;
    DiscreteBar& bar = result.bar;
    bar = uniform_bar(o.stiffness, o.segments, Segment{o.length, 0.0, o.length, 1.0});
    const double rest_rate = o.rest_growth_rate - o.shrinkage_rate; // ḣ/m
    const bool subdividing = o.max_rest_length > 0;
    const double inf = std::numeric_limits<double>::infinity();

    double t = 0.0;
    while (true) {
        set_time(bar, o, t);

        // === Subdivide the sub-segments that reached max_rest_length (Fig. A.3b)
        if (subdividing) {
            bool any = false;
            for (std::size_t j = bar.num_springs(); j-- > 0;) {
                if (bar.broken[j] || bar.rest[j] < o.max_rest_length * (1.0 - TIE_TOLERANCE)) continue;
                subdivide(bar, j);
                ++result.subdivisions;
                any = true;
            }
            if (bar.num_springs() > o.max_springs) {
                result.capped = true;
                break;
            }
            if (any) continue; // a half may still be too long
        }

        // === Equilibrium now and its rate of change
        const VecX T = spring_tensions(bar, equilibrium(bar));
        const DiscreteBar rates = rate_bar(bar, o);
        const VecX dT = spring_tensions(rates, equilibrium(rates));

        // === Break only the most stressed spring above the threshold, then re-solve
        const std::size_t worst = most_stressed(bar, T);
        if (worst < bar.num_springs() && T[static_cast<Eigen::Index>(worst)] > o.break_tension) {
            if (result.events.size() >= o.max_events) {
                result.capped = true;
                break;
            }
            result.events.push_back(
                {t, bar.midpoint(worst), worst, T[static_cast<Eigen::Index>(worst)] / o.break_tension});
            break_spring(bar, worst);
            continue;
        }

        // === Next threshold crossing: T_j + Ṫ_j·(t' − t) = T_b, earliest first, ties to the lowest index
        double t_break = inf;
        std::size_t crossing = bar.num_springs();
        for (std::size_t j = 0; j < bar.num_springs(); ++j) {
            const auto i = static_cast<Eigen::Index>(j);
            if (bar.broken[j] || !(dT[i] > 0)) continue;
            const double tj = t + std::max(0.0, (o.break_tension - T[i]) / dT[i]);
            if (tj < t_break - TIE_TOLERANCE * std::abs(t_break == inf ? tj : t_break)) {
                t_break = tj;
                crossing = j;
            }
        }

        // === Next subdivision: m_j·(1 + (q − s)·t') = max_rest_length
        double t_subdivide = inf;
        if (subdividing && rest_rate > 0) {
            for (std::size_t j = 0; j < bar.num_springs(); ++j) {
                if (bar.broken[j]) continue;
                t_subdivide = std::min(t_subdivide, (o.max_rest_length / bar.size(j) - 1.0) / rest_rate);
            }
        }

        if (t_subdivide <= t_break && t_subdivide < o.duration) {
            t = std::max(t, t_subdivide);
            continue;
        }
        if (t_break >= o.duration) {
            t = o.duration;
            break;
        }
        // The crossing spring reaches T_b exactly at t_break and is then the most stressed.
        if (result.events.size() >= o.max_events) {
            result.capped = true;
            break;
        }
        const auto i = static_cast<Eigen::Index>(crossing);
        const double T_at_break = T[i] + dT[i] * (t_break - t);
        t = t_break;
        result.events.push_back({t, bar.midpoint(crossing), crossing, T_at_break / o.break_tension});
        break_spring(bar, crossing);
    }

    // === Final state
    result.final_time = t;
    set_time(bar, o, t);
    result.positions = equilibrium(bar);
    result.tensions = spring_tensions(bar, result.positions);
    return result;
}

} // namespace crackle::fracture::bar1d
