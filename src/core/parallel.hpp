#pragma once
/// @file Splitting independent rows of work over the machine's cores. Every row is computed by
/// exactly one thread from inputs no other row writes, so results do not depend on the thread
/// count (the maps are byte-identical with 1 or 2 threads; tested).

#include <algorithm>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace crackle {

/// Holds the BLAS behind CHOLMOD (OpenBLAS, when it is the system's libblas) to one thread, so
/// that a direct solve sums in the same order on every machine: with its own thread count
/// (OPENBLAS_NUM_THREADS, else the cores) a 600-element mud run with the direct solver made 257
/// fragments on 2 threads and 254 on 1 (issue 16). One thread costs nothing measurable here
/// (mass-spring bark 4.27 s either way). Called once by main and the test runner.
void pin_blas_threads();

/// Worker threads for image passes: $CRACKLE_THREADS if set (≥ 1), else the hardware's count.
inline int worker_threads() {
    if (const char* env = std::getenv("CRACKLE_THREADS")) {
        const int n = std::atoi(env);
        if (n >= 1) return std::min(n, 64);
    }
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

/// Calls body(row) for row in [0, rows), rows interleaved over the worker threads.
template <typename Body> void parallel_rows(int rows, const Body& body) {
    const int threads = std::min(worker_threads(), std::max(1, rows / 16));
    if (threads <= 1) {
        for (int r = 0; r < rows; ++r)
            body(r);
        return;
    }
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(threads - 1));
    auto run = [&](int first) {
        for (int r = first; r < rows; r += threads)
            body(r);
    };
    for (int t = 1; t < threads; ++t)
        pool.emplace_back(run, t);
    run(0);
    for (auto& th : pool)
        th.join();
}

} // namespace crackle
