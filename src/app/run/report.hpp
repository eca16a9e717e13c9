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
/// version, the tile size in metres, every key as the run's plan resolved it ("settings") and
/// where the pattern came from.
Json simulation_report(const SimulationResult& r, const StepTimes& times);

void print_times(std::ostream& out, const StepTimes& times);
void print_simulation(std::ostream& out, const SimulationResult& r);

} // namespace crackle::app
