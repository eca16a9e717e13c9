#pragma once
/// @file Progress of a whole run on stderr: a bar on a terminal, or one JSON object per line for
/// render farms (`--progress`, $CRACKLE_PROGRESS).
///
/// A run is a plan of stages with rough weights (ProgressPlan, set up by the app: setup,
/// fracture, post, bake, encode, write). The Progress objects of long loops report their own
/// fraction into the current stage, and a Progress whose label names a stage of the plan enters
/// that stage. The report shows the stage, the whole run's fraction, the elapsed time and an ETA.
/// Without a plan, a Progress is a run of one stage of its own.
///
/// Progress only reads a clock and writes to stderr: it never changes a result. Everything here
/// is meant for the main thread.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace crackle {

// === Modes and hooks

/// How progress is reported: `Auto` draws a bar when stderr is a terminal and nothing
/// otherwise; `Json` writes one JSON object per line (docs: README, "Progress").
enum class ProgressMode { Auto, Bar, Json, None };

/// Parses "auto", "bar", "json" or "none"; nullopt for anything else.
std::optional<ProgressMode> parse_progress_mode(std::string_view text);

/// "" for a valid mode, else what is wrong (the CLI's check of --progress and $CRACKLE_PROGRESS).
std::string progress_mode_check(const std::string& text);

/// Sets the mode (Auto is resolved here, with one isatty(stderr)). The default is Auto.
void set_progress_mode(ProgressMode mode);

/// Globally enables or disables progress reports (the CLI's --quiet turns them off, whatever
/// the mode).
void set_progress_enabled(bool enabled);

/// Replaces the wall clock (seconds, non-decreasing) for tests; an empty function restores the
/// steady clock.
void set_progress_clock(std::function<double()> clock);

/// Replaces the output (stderr) for tests; an empty function restores stderr. The sink gets
/// whole pieces of output: a JSON line with its '\n', or a bar redraw starting with '\r'.
void set_progress_sink(std::function<void(const std::string&)> sink);

/// Removes a bar from the terminal line before other text goes to stderr (the log calls it);
/// the next update draws it again.
void progress_clear_line();

// === A run's plan

/// One stage of a run.
struct ProgressStage {
    std::string name; ///< what the report calls it: "fracture"
    /// Rough expected wall time in seconds (from element count, map size); only its ratio to
    /// the others matters until the stage has run. 0 = unknown.
    double weight = 0;
};

/// The stages of the whole run, process-wide while the object lives. The first stage starts at
/// once; later ones start with enter() / progress_stage() or with a Progress named after them.
/// Destroying it normally reports "done" (fraction 1); destroying it during stack unwinding
/// only ends the bar's line.
class ProgressPlan {
public:
    explicit ProgressPlan(std::vector<ProgressStage> stages);
    ~ProgressPlan();
    ProgressPlan(const ProgressPlan&) = delete;
    ProgressPlan& operator=(const ProgressPlan&) = delete;

    /// Starts the named stage (progress_stage()).
    void enter(const std::string& stage);

private:
    int m_exceptions;
    bool m_owner;
};

/// Starts the named stage of the current plan; stages in between count as done. Does nothing
/// without a plan, for a name the plan lacks, or for a stage already passed.
void progress_stage(const std::string& name);

/// One report, as the JSON lines and the bar see it.
struct ProgressSnapshot {
    std::string stage;           ///< current stage, "done" at the end
    double fraction = 0;         ///< of the whole run, in [0, 1], never decreasing
    double elapsed_s = 0;        ///< since the plan began
    std::optional<double> eta_s; ///< smoothed remaining time; nullopt until meaningful
};

/// Formats one JSON line: {"event":"progress","stage":…,"fraction":…,"elapsed_s":…,"eta_s":…}
/// with a trailing '\n'; numbers are finite, eta_s is null when unknown.
std::string progress_json_line(const ProgressSnapshot& snapshot);

// === Loops

/// Reports a loop's own progress into the current stage (or draws a run of its own when no plan
/// is active). Cheap when nothing is drawn: one clock read, no system call.
class Progress {
public:
    /// @param label  what is running ("repulsion"); a plan's stage of this name is entered
    /// @param total  number of work units (iterations, tiles); 0 = unknown
    Progress(std::string label, double total);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Reports `done` of `total` units finished.
    void update(double done);
    void finish();

private:
    double m_total;
    bool m_active;
    bool m_owns_plan = false;
};

/// The fraction of a fracture run by work rather than simulated time. Nothing breaks before the
/// first fracture, and the loop gets there in one or two time steps; from then on the cost
/// follows the events and the time steps, dense at first and sparser later.
///
/// Measured with `crackle simulate PRESET` (fem-split, default elements, 2 shared cores) and a
/// temporary line in the loop printing t, wall time and events at every iteration; s =
/// (t − t₁)/(T − t₁) after the first fracture at t₁:
///
///     preset  elements  loop wall  events   t₁     s at 25 / 50 / 75 % of the loop's wall time
///     bark      2222      1.8 s      694   0.244   0.02 / 0.11 / 0.38
///     mud       5000     32.8 s     2504   0.406   0.04 / 0.21 / 0.48
///     fruit     6980      7.2 s     2546   0.666   0.00 / 0.05 / 0.42  (72 % of the events in
///                                                  one cascade at t₁, 45 % of the wall time)
///
/// Wall time against s is close to s^(1/3) on all three (at s = 0.1: 0.48, 0.39 and 0.54 of the
/// wall time after t₁; 0.1^(1/3) = 0.46), except in fruit's opening cascade, where s stands
/// still. The events count that part, against an expected 0.4 per initial element (0.31, 0.50
/// and 0.36 here), saturating below 1:
///
///     f = P·t/T before t₁;   f = b + (1 − b)·max(s^(1/3), n/(n + n_exp)) after, b = P·t₁/T
///
/// with P = 0.02. Both terms only grow, so f never goes backwards. Fraction at 25 / 50 / 75 % of
/// the loop's wall time, t/T before → f now: bark 0.26 / 0.33 / 0.55 → 0.29 / 0.49 / 0.74; mud
/// 0.43 / 0.49 / 0.67 → 0.33 / 0.52 / 0.77; fruit 0.67 / 0.71 / 0.82 → 0.33 / 0.53 / 0.77. At
/// 50 % also: bark with 1000 elements 0.39, mud 2000 0.49, fruit 3000 0.53, mud/thin 0.58,
/// sphere/crackle-glaze 0.59, bark/table-5-2-a 0.36, bark/flowering-dogwood 0.70.
struct FractureWork {
    double duration = 1;          ///< T, simulated time of the run
    double expected_events = 1;   ///< n_exp, a rough count (0.4 per initial element)
    double first_event_time = -1; ///< t₁/T; negative until the first event

    /// The fraction of the run done at simulated time `time` with `events` events so far; call
    /// with non-decreasing time and events (remembers t₁ on the first call with events > 0).
    double fraction(double time, std::size_t events);
};

/// A fracture loop's Progress ("fracture" stage), by FractureWork.
class FractureProgress {
public:
    /// @param duration         simulated time of the run
    /// @param initial_elements elements (or springs / 3) at the start, for the expected events
    FractureProgress(double duration, std::size_t initial_elements);
    void update(double time, std::size_t events) { m_progress.update(m_work.fraction(time, events)); }
    void finish() { m_progress.finish(); }

private:
    FractureWork m_work;
    Progress m_progress;
};

} // namespace crackle
