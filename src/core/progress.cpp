#include "core/progress.hpp"

#include "core/budget.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <unistd.h>

namespace crackle {
namespace {

constexpr double BAR_DELAY_S = 1.0;       ///< no bar for runs shorter than this
constexpr double BAR_INTERVAL_S = 0.1;    ///< redraws at most this often
constexpr double JSON_INTERVAL_S = 1.0;   ///< JSON lines at most this often (and on stage changes)
constexpr double ETA_MIN_ELAPSED_S = 3.0; ///< an ETA only after this long...
constexpr double ETA_MIN_FRACTION = 0.05; ///< ...and this much of the run
constexpr double ETA_SMOOTHING_S = 2.0;   ///< time constant of the ETA's smoothing

enum class Output { None, Bar, Json };

double steady_seconds() {
    using Clock = std::chrono::steady_clock;
    static const Clock::time_point start = Clock::now();
    return std::chrono::duration<double>(Clock::now() - start).count();
}

std::string fixed(double v, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, std::isfinite(v) ? v : 0.0);
    return buf;
}

/// "42s", "3m07s", "1h02m": the ETA as a person reads it.
std::string duration_text(double s) {
    const long long total = std::llround(std::max(0.0, s));
    char buf[32];
    if (total < 60)
        std::snprintf(buf, sizeof buf, "%llds", total);
    else if (total < 3600)
        std::snprintf(buf, sizeof buf, "%lldm%02llds", total / 60, total % 60);
    else
        std::snprintf(buf, sizeof buf, "%lldh%02lldm", total / 3600, (total % 3600) / 60);
    return buf;
}

/// The process-wide reporter: the plan, its clock and its output.
struct Reporter {
    // === Settings (Auto until the CLI says otherwise)
    std::atomic<bool> enabled{true};
    std::atomic<Output> output{::isatty(STDERR_FILENO) == 1 ? Output::Bar : Output::None};
    std::function<double()> clock;
    std::function<void(const std::string&)> sink;

    // === The plan
    struct Stage {
        ProgressStage plan;
        double seconds = 0; ///< actual wall time, once passed
    };
    std::vector<Stage> stages;
    bool active = false;
    std::size_t current = 0;
    double run_start = 0, stage_start = 0;
    double sub = 0; ///< the current stage's own fraction

    // === What was reported
    double fraction = 0;
    double last_emit = -1e300;
    double eta = -1, eta_time = 0; ///< smoothed ETA (−1: none yet) and when it was computed
    bool bar_on_line = false, bar_shown = false;

    double now() const { return clock ? clock() : steady_seconds(); }
    void write(const std::string& text) const {
        if (sink) {
            sink(text);
            return;
        }
        std::fputs(text.c_str(), stderr);
        std::fflush(stderr);
    }
    Output mode() const { return enabled ? output.load() : Output::None; }

    void begin(std::vector<ProgressStage> plan) {
        stages.clear();
        for (ProgressStage& s : plan)
            stages.push_back({std::move(s), 0.0});
        if (stages.empty()) stages.push_back({{"run", 0.0}, 0.0});
        active = true;
        current = 0;
        run_start = stage_start = now();
        sub = 0;
        fraction = 0;
        last_emit = -1e300;
        eta = -1;
        bar_on_line = bar_shown = false;
        report(run_start, true);
    }

    void enter(const std::string& name) {
        if (!active) return;
        for (std::size_t i = current + 1; i < stages.size(); ++i) {
            if (stages[i].plan.name != name) continue;
            const double t = now();
            stages[current].seconds = t - stage_start;
            for (std::size_t k = current + 1; k < i; ++k)
                stages[k].seconds = 0; // skipped: nothing left to do there
            current = i;
            stage_start = t;
            sub = 0;
            report(t, true);
            return;
        }
    }

    void set_sub(double f) {
        if (!active || !(f > sub)) return; // NaN and going back are ignored
        sub = std::min(f, 1.0);
    }

    /// Expected wall time of the whole run: stages passed as they took, the current one from
    /// its weight blended with its own rate, the rest by weight.
    double expected_total(double t) const {
        double total = 0;
        for (std::size_t i = 0; i < current; ++i)
            total += stages[i].seconds;
        total += expected_current(t);
        for (std::size_t i = current + 1; i < stages.size(); ++i)
            total += stages[i].plan.weight;
        return total;
    }

    /// Expected wall time of the current stage. Its rate so far (elapsed / sub) takes over from
    /// the weight as the stage goes on: wholly from half-way, or at once without a weight.
    double expected_current(double t) const {
        const double elapsed = t - stage_start, weight = stages[current].plan.weight;
        if (sub >= 1) return elapsed;
        if (sub <= 0) return std::max(weight, elapsed);
        const double by_rate = elapsed / sub;
        const double trust = weight > 0 ? std::min(1.0, 2.0 * sub) : 1.0;
        return std::max(elapsed, (1 - trust) * std::max(weight, elapsed) + trust * by_rate);
    }

    /// The run's fraction: the current stage counts its own fraction of its expected time.
    double raw_fraction(double t) const {
        double passed = 0;
        for (std::size_t i = 0; i < current; ++i)
            passed += stages[i].seconds;
        const double total = expected_total(t);
        if (!(total > 0)) return sub;
        return std::clamp((passed + sub * expected_current(t)) / total, 0.0, 1.0);
    }

    ProgressSnapshot snapshot(double t) {
        ProgressSnapshot s;
        s.stage = stages[current].plan.name;
        fraction = std::max(fraction, std::min(raw_fraction(t), 0.999));
        s.fraction = fraction;
        s.elapsed_s = t - run_start;
        // Smoothed ETA: the last one counted down, pulled towards the current estimate.
        const double estimate = std::max(0.0, expected_total(t) - s.elapsed_s);
        if (eta < 0) {
            eta = estimate;
        } else {
            const double dt = std::max(0.0, t - eta_time);
            const double predicted = std::max(0.0, eta - dt);
            eta = predicted + (1 - std::exp(-dt / ETA_SMOOTHING_S)) * (estimate - predicted);
        }
        eta_time = t;
        const bool known = sub > 0 || stages[current].plan.weight > 0 || current > 0;
        if (s.elapsed_s >= ETA_MIN_ELAPSED_S && fraction >= ETA_MIN_FRACTION && known && std::isfinite(eta))
            s.eta_s = eta;
        return s;
    }

    /// Reports when due: JSON lines once a second and at every stage change, the bar after the
    /// first second every 0.1 s.
    void report(double t, bool stage_changed) {
        switch (mode()) {
        case Output::None:
            return;
        case Output::Json:
            if (!stage_changed && t - last_emit < JSON_INTERVAL_S) return;
            last_emit = t;
            write(progress_json_line(snapshot(t)));
            return;
        case Output::Bar:
            if (t - run_start < BAR_DELAY_S || t - last_emit < BAR_INTERVAL_S) return;
            last_emit = t;
            draw(snapshot(t));
            return;
        }
    }

    void draw(const ProgressSnapshot& s) {
        constexpr int WIDTH = 30;
        const auto filled = static_cast<std::size_t>(s.fraction * WIDTH);
        std::string bar(filled, '#');
        bar.resize(WIDTH, '-');
        char line[160];
        std::snprintf(line, sizeof line, "\r%-14s [%s] %5.1f%%  %6.1fs  ETA %-8s", s.stage.c_str(), bar.c_str(),
                      100.0 * s.fraction, s.elapsed_s, s.eta_s ? duration_text(*s.eta_s).c_str() : "--");
        write(line);
        bar_on_line = bar_shown = true;
    }

    void end(bool completed) {
        if (!active) return;
        const double t = now();
        stages[current].seconds = t - stage_start;
        if (completed) {
            fraction = 1;
            ProgressSnapshot s;
            s.stage = "done";
            s.fraction = 1;
            s.elapsed_s = t - run_start;
            s.eta_s = 0.0;
            if (mode() == Output::Json) write(progress_json_line(s));
            if (mode() == Output::Bar && bar_shown) draw(s);
        }
        if (bar_on_line) write("\n");
        bar_on_line = bar_shown = false;
        active = false;
    }

    void clear_line() {
        if (!bar_on_line) return;
        write("\r" + std::string(80, ' ') + "\r");
        bar_on_line = false;
        last_emit = -1e300; // draw again at the next update
    }
};

Reporter& reporter() {
    static Reporter r;
    return r;
}

} // namespace

// === Modes and hooks

std::optional<ProgressMode> parse_progress_mode(std::string_view text) {
    if (text == "auto") return ProgressMode::Auto;
    if (text == "bar") return ProgressMode::Bar;
    if (text == "json") return ProgressMode::Json;
    if (text == "none") return ProgressMode::None;
    return std::nullopt;
}

std::string progress_mode_check(const std::string& text) {
    if (parse_progress_mode(text)) return "";
    return "expected auto, bar, json or none (from --progress or $CRACKLE_PROGRESS), got '" + text + "'";
}

void set_progress_mode(ProgressMode mode) {
    Output out = Output::None;
    switch (mode) {
    case ProgressMode::Auto:
        out = ::isatty(STDERR_FILENO) == 1 ? Output::Bar : Output::None;
        break;
    case ProgressMode::Bar:
        out = Output::Bar;
        break;
    case ProgressMode::Json:
        out = Output::Json;
        break;
    case ProgressMode::None:
        break;
    }
    reporter().output = out;
}

void set_progress_enabled(bool enabled) {
    reporter().enabled = enabled;
}

void set_progress_clock(std::function<double()> clock) {
    reporter().clock = std::move(clock);
}

void set_progress_sink(std::function<void(const std::string&)> sink) {
    reporter().sink = std::move(sink);
}

void progress_clear_line() {
    reporter().clear_line();
}

// === A run's plan

ProgressPlan::ProgressPlan(std::vector<ProgressStage> stages)
    : m_exceptions(std::uncaught_exceptions()), m_owner(!reporter().active) {
    // A plan inside a plan (a command run by another) leaves the outer one in charge.
    if (m_owner) reporter().begin(std::move(stages));
}

ProgressPlan::~ProgressPlan() {
    if (m_owner) reporter().end(std::uncaught_exceptions() <= m_exceptions);
}

void ProgressPlan::enter(const std::string& stage) {
    if (m_owner) reporter().enter(stage);
}

void progress_stage(const std::string& name) {
    reporter().enter(name);
}

std::string progress_json_line(const ProgressSnapshot& s) {
    std::string name;
    for (const char c : s.stage) {
        if (c == '"' || c == '\\') name += '\\';
        if (static_cast<unsigned char>(c) >= 0x20) name += c;
    }
    const double fraction = std::isfinite(s.fraction) ? std::clamp(s.fraction, 0.0, 1.0) : 0.0;
    std::string line = "{\"event\":\"progress\",\"stage\":\"" + name + "\",\"fraction\":";
    line += fraction >= 1 ? std::string("1") : fixed(fraction, 4);
    line += ",\"elapsed_s\":" + fixed(std::max(0.0, s.elapsed_s), 1);
    line += ",\"eta_s\":";
    line += s.eta_s && std::isfinite(*s.eta_s) ? fixed(std::max(0.0, *s.eta_s), 1) : std::string("null");
    return line + "}\n";
}

// === Loops

Progress::Progress(std::string label, double total) : m_total(total), m_active(reporter().mode() != Output::None) {
    if (!m_active) return;
    Reporter& r = reporter();
    if (!r.active) {
        r.begin({{std::move(label), 0.0}});
        m_owns_plan = true;
    } else {
        r.enter(label);
    }
}

Progress::~Progress() {
    finish();
}

void Progress::update(double done) {
    budget_check(); // every long loop reports here, so every long loop stops here (core/budget.hpp)
    if (!m_active) return;
    Reporter& r = reporter();
    if (m_total > 0) r.set_sub(done / m_total);
    r.report(r.now(), false);
}

void Progress::finish() {
    if (!m_active) return;
    m_active = false;
    Reporter& r = reporter();
    if (m_owns_plan) {
        r.end(true);
        return;
    }
    r.set_sub(1.0);
    r.report(r.now(), false);
}

// === Fracture loops

double FractureWork::fraction(double time, std::size_t events) {
    constexpr double BEFORE_FIRST = 0.02; // P: the share before the first fracture
    if (!(duration > 0)) return 0;
    const double t = std::clamp(time / duration, 0.0, 1.0);
    if (events == 0 && first_event_time < 0) return BEFORE_FIRST * t;
    if (first_event_time < 0) first_event_time = t;
    const double t1 = first_event_time, base = BEFORE_FIRST * t1;
    const double s = t1 < 1 ? std::clamp((t - t1) / (1 - t1), 0.0, 1.0) : 1.0;
    const double n = static_cast<double>(events);
    const double by_time = std::cbrt(s), by_events = n / (n + std::max(expected_events, 1.0));
    return base + (1 - base) * std::max(by_time, by_events);
}

FractureProgress::FractureProgress(double duration, std::size_t initial_elements)
    : m_work{duration, 0.4 * static_cast<double>(initial_elements), -1.0}, m_progress("fracture", 1.0) {}

} // namespace crackle
