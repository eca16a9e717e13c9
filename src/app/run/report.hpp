#pragma once
/// @file The report of a run (design.md, "The report every simulate and bake can write") and
/// the summary lines printed on the terminal.

#include "app/run/pipeline.hpp"
#include "core/json.hpp"
#include "core/timer.hpp"

#include <ostream>
#include <string>

namespace crackle::app {

/// This crackle's version (CMake's project version).
const char* crackle_version();

/// printf-style formatting of one number.
std::string fmt(const char* format, double v);

/// The report fields of design.md for a finished simulation, plus details: the crackle
/// version, the tile size in metres, every resolved preset value ("settings") and where the
/// pattern came from.
Json simulation_report(const io::Preset& preset, const SimulationResult& r, const StepTimes& times);

/// The preset's resolved values as JSON, key → value (simulation.elements = "auto" as the
/// plan's count).
Json resolved_settings(const io::Preset& preset, const RunPlan& plan);

void print_times(std::ostream& out, const StepTimes& times);
void print_simulation(std::ostream& out, const SimulationResult& r);

} // namespace crackle::app
