#pragma once
/// @file `crackle bench`: measured speed (and, as methods arrive, accuracy) on fixed scenes.
/// Benchmarks never run in the test suite; their figures go to docs/benchmarks.md.

#include <ostream>
#include <string>
#include <vector>

namespace crackle::app {

struct BenchArgs {
    bool quick = false;              ///< small sizes, for a smoke run
    std::string out_dir;             ///< where bench.json goes ("" = nowhere)
    std::vector<std::string> scenes; ///< empty = all
};

/// Runs the scenes and prints Markdown tables. Scenes: "solve" (equilibrium, CG vs direct),
/// "fem-remove" (mud runs to completion), "bake" (texture sets at several sizes).
int bench_command(const BenchArgs& args, std::ostream& out);

/// The scene names `bench` knows.
const std::vector<std::string>& bench_scenes();

} // namespace crackle::app
