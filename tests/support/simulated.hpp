#pragma once
/// @file A preset simulated and built into pieces in-process, for tests of the post stage and
/// the bake.

#include "app/run/options.hpp"
#include "app/run/pipeline.hpp"
#include "io/preset.hpp"
#include "post/pieces.hpp"

#include <string>
#include <vector>

namespace crackle::test {

struct Simulated {
    io::Preset preset;
    app::SimulationResult run;
    post::PieceMesh pieces;
};

/// `name` with `--set`-style overrides, simulated and built into pieces.
inline Simulated simulate(const std::string& name, const std::vector<std::string>& overrides) {
    io::PresetRequest request;
    request.name_or_path = name;
    request.overrides = overrides;
    Simulated s{io::load_preset(request), {}, {}};
    StepTimes times;
    s.run = app::run_simulation(app::make_run_plan(s.preset), times);
    s.pieces = post::build_pieces(s.run.pattern, app::post_options(s.preset));
    return s;
}

} // namespace crackle::test
