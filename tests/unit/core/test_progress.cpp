#include "core/json.hpp"
#include "core/progress.hpp"
#include "support/cli_runner.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

using namespace crackle;

namespace {

/// Routes progress to a string on a fake clock for one test, and restores stderr, the steady
/// clock and the quiet default afterwards (other tests run the CLI in this process).
struct CapturedProgress {
    double now = 100.0; // any origin: only differences count
    std::string text;
    explicit CapturedProgress(ProgressMode mode) {
        set_progress_clock([this] { return now; });
        set_progress_sink([this](const std::string& s) { text += s; });
        set_progress_enabled(true);
        set_progress_mode(mode);
    }
    ~CapturedProgress() {
        set_progress_mode(ProgressMode::None);
        set_progress_sink({});
        set_progress_clock({});
    }
    CapturedProgress(const CapturedProgress&) = delete;
    CapturedProgress& operator=(const CapturedProgress&) = delete;

    std::vector<std::string> lines() const {
        std::vector<std::string> out;
        std::istringstream is(text);
        for (std::string line; std::getline(is, line);)
            out.push_back(line);
        return out;
    }
};

/// A parsed progress line, checked for the fixed keys in their fixed order.
struct Line {
    std::string stage;
    double fraction = 0, elapsed = 0;
    bool has_eta = false;
    double eta = 0;
};

Line parse_line(const std::string& text) {
    CAPTURE(text);
    const Json j = Json::parse(text, "progress line");
    REQUIRE(j.is_object());
    std::vector<std::string> keys;
    for (const auto& [key, value] : j.members())
        keys.push_back(key);
    REQUIRE(keys == std::vector<std::string>{"event", "stage", "fraction", "elapsed_s", "eta_s"});
    CHECK(j.find("event")->as_string() == "progress");
    Line l;
    l.stage = j.find("stage")->as_string();
    REQUIRE(j.find("fraction")->is_number());
    REQUIRE(j.find("elapsed_s")->is_number());
    l.fraction = j.find("fraction")->as_number();
    l.elapsed = j.find("elapsed_s")->as_number();
    const Json& eta = *j.find("eta_s");
    l.has_eta = eta.is_number();
    if (l.has_eta)
        l.eta = eta.as_number();
    else
        CHECK(text.find("\"eta_s\":null") != std::string::npos);
    CHECK(std::isfinite(l.fraction));
    CHECK(std::isfinite(l.elapsed));
    CHECK((!l.has_eta || (std::isfinite(l.eta) && l.eta >= 0)));
    return l;
}

/// A staged run like `crackle bake`: setup with a sub-loop, a slow fracture, stages without
/// loops, and a bake loop. Stage weights are deliberately off (fracture takes 4× its weight).
void staged_run(CapturedProgress& c) {
    ProgressPlan plan({{"setup", 1.0}, {"fracture", 10.0}, {"post", 0.5}, {"bake", 8.0}, {"write", 0.1}});
    {
        Progress repulsion("repulsion", 20); // not a stage: reports into setup
        for (int i = 1; i <= 20; ++i) {
            c.now += 0.05;
            repulsion.update(i);
        }
    }
    FractureProgress fracture(1.0, 1000);
    std::size_t events = 0;
    for (int i = 0; i <= 400; ++i) {
        const double t = i < 100 ? 0.4 * i / 100.0 : 0.4 + 0.6 * (i - 100) / 300.0;
        if (i >= 100) events += i < 150 ? 8 : 1; // a cascade at the first fracture, then fewer
        c.now += 0.1;
        fracture.update(t, events);
    }
    fracture.finish();
    progress_stage("post");
    c.now += 0.4;
    Progress bake("bake", 16);
    for (int tile = 1; tile <= 16; ++tile) {
        c.now += 0.6;
        bake.update(tile);
    }
    bake.finish();
    plan.enter("write");
    c.now += 0.2;
}

} // namespace

TEST_SUITE("core") {
    TEST_CASE("progress: json lines parse with fixed keys, at most one a second plus stage changes, and end in done") {
        CapturedProgress c(ProgressMode::Json);
        staged_run(c);
        const std::vector<std::string> lines = c.lines();
        REQUIRE(lines.size() >= 10);
        std::vector<Line> parsed;
        for (const std::string& text : lines)
            parsed.push_back(parse_line(text));

        // Every stage shows up, in order, the first one at once; the last line is done.
        std::vector<std::string> stages;
        for (const Line& l : parsed)
            if (stages.empty() || stages.back() != l.stage) stages.push_back(l.stage);
        CHECK(stages == std::vector<std::string>{"setup", "fracture", "post", "bake", "write", "done"});
        CHECK(parsed.front().elapsed == 0.0);
        CHECK(parsed.back().stage == "done");
        CHECK(parsed.back().fraction == 1.0);
        CHECK(std::count_if(parsed.begin(), parsed.end(), [](const Line& l) { return l.stage == "done"; }) == 1);

        // Within a stage, lines are at least a second apart (elapsed_s is rounded to 0.1 s, hence 0.85).
        for (std::size_t i = 1; i + 1 < parsed.size(); ++i)
            if (parsed[i].stage == parsed[i - 1].stage) {
                CAPTURE(i);
                CHECK(parsed[i].elapsed - parsed[i - 1].elapsed >= 0.85);
            }
    }

    TEST_CASE(
        "progress: a staged run's fraction stays in [0, 1], never decreases, and its ETA appears once meaningful") {
        CapturedProgress c(ProgressMode::Json);
        staged_run(c);
        double last = 0;
        bool eta_seen = false;
        for (const std::string& text : c.lines()) {
            const Line l = parse_line(text);
            CAPTURE(text);
            CHECK(l.fraction >= 0.0);
            CHECK(l.fraction <= 1.0);
            CHECK(l.fraction >= last);
            last = l.fraction;
            // "ETA --" for the first seconds, then a number for the rest of the run.
            if (l.elapsed < 3.0) CHECK_FALSE(l.has_eta);
            if (eta_seen) CHECK(l.has_eta);
            eta_seen = eta_seen || l.has_eta;
        }
        CHECK(eta_seen);
        CHECK(last == 1.0);
    }

    TEST_CASE("progress: the ETA of a steady run converges on the true remaining time") {
        // One stage, 100 s, steady: after half the run the ETA is within a few seconds of 50 s.
        CapturedProgress c(ProgressMode::Json);
        {
            Progress p("steady", 100);
            for (int i = 1; i <= 50; ++i) {
                c.now += 1.0;
                p.update(i);
            }
        }
        const std::vector<std::string> lines = c.lines();
        REQUIRE(lines.size() >= 3);
        const Line half = parse_line(lines[lines.size() - 2]);
        CHECK(half.stage == "steady");
        CHECK(half.fraction == doctest::Approx(0.5).epsilon(0.01));
        REQUIRE(half.has_eta);
        CHECK(half.eta == doctest::Approx(50.0).epsilon(0.1));
        CHECK(parse_line(lines.back()).stage == "done"); // a Progress without a plan is its own run
    }

    TEST_CASE("progress: the bar stays away for the first second, names the stage and ends its line") {
        CapturedProgress c(ProgressMode::Bar);
        {
            ProgressPlan plan({{"setup", 1.0}, {"fracture", 4.0}});
            Progress quick("repulsion", 10);
            for (int i = 1; i <= 5; ++i) {
                c.now += 0.1;
                quick.update(i);
            }
            CHECK(c.text.empty()); // half a second: nothing drawn
            quick.finish();
            FractureProgress fracture(1.0, 100);
            for (int i = 1; i <= 50; ++i) {
                c.now += 0.1;
                fracture.update(0.02 * i, static_cast<std::size_t>(i));
            }
            CHECK(c.text.find("fracture") != std::string::npos);
            CHECK(c.text.find("ETA --") != std::string::npos); // early: no estimate yet
            CHECK(c.text.find('\n') == std::string::npos);     // one line, redrawn in place
            progress_clear_line();                             // a log message wipes it...
            CHECK(c.text.back() == '\r');
        }
        CHECK(c.text.find("done") != std::string::npos); // ...and the end draws 100 % and a newline
        CHECK(c.text.find("100.0%") != std::string::npos);
        CHECK(c.text.back() == '\n');
    }

    TEST_CASE("progress: none and quiet report nothing, and cost no output") {
        CapturedProgress c(ProgressMode::None);
        {
            ProgressPlan plan({{"setup", 1.0}});
            Progress p("loop", 10);
            for (int i = 1; i <= 10; ++i) {
                c.now += 1.0;
                p.update(i);
            }
        }
        set_progress_mode(ProgressMode::Json);
        set_progress_enabled(false); // -q wins over the mode
        {
            Progress p("loop", 10);
            c.now += 5.0;
            p.update(5);
        }
        set_progress_enabled(true);
        CHECK(c.text.empty());
    }

    TEST_CASE("progress: the fracture work fraction is monotone, in [0, 1], and moves during a cascade") {
        // Simulated time runs ahead while nothing breaks, then a cascade at t₁ = 0.6 where time
        // stands still, then sparse events: the fraction never goes back, starts small, and
        // ends at exactly 1.
        for (const double duration : {1.0, 8e-5}) {
            CAPTURE(duration);
            FractureWork work{duration, 400.0, -1.0};
            double last = 0;
            std::size_t events = 0;
            std::vector<double> seen;
            for (int i = 0; i <= 1000; ++i) {
                const double t = i < 300 ? 0.6 * i / 300.0 : i < 600 ? 0.6 : 0.6 + 0.4 * (i - 600) / 400.0;
                if (i >= 300) events += i < 600 ? 3 : (i % 7 == 0 ? 1 : 0);
                const double f = work.fraction(t * duration, events);
                CAPTURE(i);
                CHECK(f >= last);
                CHECK(f >= 0.0);
                CHECK(f <= 1.0);
                last = f;
                seen.push_back(f);
            }
            CHECK(seen[299] <= 0.02);                   // before the first fracture: a sliver
            CHECK(seen[599] - seen[300] > 0.3);         // the cascade moves the bar at fixed t
            CHECK(seen.back() == doctest::Approx(1.0)); // the end of simulated time is the end
        }
        // Without any event, simulated time alone carries it (to P = 2 % at the end; the loop
        // then finishes the stage).
        FractureWork quiet{1.0, 400.0, -1.0};
        CHECK(quiet.fraction(0.5, 0) == doctest::Approx(0.01));
        // Over a grid of (time, events), more of either never lowers the fraction once t₁ is
        // known.
        for (double t = 0.3; t <= 1.0; t += 0.1)
            for (std::size_t n = 1; n < 3000; n += 250) {
                FractureWork w{1.0, 400.0, 0.3};
                CAPTURE(t);
                CAPTURE(n);
                CHECK(w.fraction(t, n + 100) >= w.fraction(t, n));
                CHECK(w.fraction(std::min(1.0, t + 0.05), n) >= w.fraction(t, n));
            }
    }

    TEST_CASE("progress: modes parse, json lines keep their keys for odd values") {
        CHECK(parse_progress_mode("auto") == ProgressMode::Auto);
        CHECK(parse_progress_mode("bar") == ProgressMode::Bar);
        CHECK(parse_progress_mode("json") == ProgressMode::Json);
        CHECK(parse_progress_mode("none") == ProgressMode::None);
        CHECK_FALSE(parse_progress_mode("JSON").has_value());
        CHECK_FALSE(parse_progress_mode("").has_value());
        CHECK(progress_mode_check("json").empty());
        CHECK(progress_mode_check("bogus").find("auto, bar, json or none") != std::string::npos);
        ProgressSnapshot odd;
        odd.stage = "a \"quoted\" stage";
        odd.fraction = std::nan("");
        odd.elapsed_s = 1e300 * 1e10; // inf
        odd.eta_s = std::nan("");
        const Line l = parse_line(progress_json_line(odd));
        CHECK(l.stage == "a \"quoted\" stage");
        CHECK(l.fraction == 0.0);
        CHECK_FALSE(l.has_eta);
    }

    TEST_CASE("cli: --progress=bogus and CRACKLE_PROGRESS=bogus exit 2 naming the modes, and -q silences json") {
        const auto flag = test::run_cli({"--progress=bogus", "presets", "list"});
        CHECK(flag.code == 2);
        CHECK(flag.err.find("--progress") != std::string::npos);
        CHECK(flag.err.find("expected auto, bar, json or none") != std::string::npos);
        CHECK(flag.err.find("'bogus'") != std::string::npos);
        CHECK(flag.out.empty());

        // The flag also works after the subcommand (global flags fall through).
        CHECK(test::run_cli({"presets", "list", "--progress", "none"}).code == 0);

        ::setenv("CRACKLE_PROGRESS", "bogus", 1);
        const auto env = test::run_cli({"presets", "list"});
        const auto flag_wins = test::run_cli({"--progress=none", "presets", "list"});
        ::unsetenv("CRACKLE_PROGRESS");
        CHECK(env.code == 2);
        CHECK(env.err.find("CRACKLE_PROGRESS") != std::string::npos);
        CHECK(flag_wins.code == 0);

        // A real command in json mode reports through the sink and ends in done; with -q, nothing.
        std::string captured;
        set_progress_sink([&captured](const std::string& s) { captured += s; });
        const std::vector<std::string> mesh = {"mesh", "mud", "--set", "simulation.elements=400"};
        std::vector<std::string> json = {"--progress=json"}, quiet = {"-q", "--progress=json"};
        json.insert(json.end(), mesh.begin(), mesh.end());
        quiet.insert(quiet.end(), mesh.begin(), mesh.end());
        CHECK(test::run_cli(json).code == 0);
        const std::string loud = captured;
        captured.clear();
        CHECK(test::run_cli(quiet).code == 0);
        set_progress_sink({});
        set_progress_mode(ProgressMode::None);
        set_progress_enabled(true);
        CHECK(captured.empty());
        REQUIRE_FALSE(loud.empty());
        std::istringstream is(loud);
        std::string line, last;
        while (std::getline(is, line)) {
            parse_line(line);
            last = line;
        }
        CHECK(parse_line(last).stage == "done");
    }
}
