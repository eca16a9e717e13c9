#pragma once
/// @file Splitting independent rows of work over the machine's cores. Every row is computed by
/// exactly one thread from inputs no other row writes, so results do not depend on the thread
/// count (the maps are byte-identical with 1 or 2 threads; tested).

#include <algorithm>
#include <atomic>
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

/// Calls body(row) for row in [0, rows), rows interleaved over the worker threads (at least
/// `least_rows` rows per thread: cheap rows are not worth a thread each).
template <typename Body> void parallel_rows(int rows, const Body& body, int least_rows = 16) {
    const int threads = std::min(worker_threads(), std::max(1, rows / std::max(least_rows, 1)));
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

/// Calls body(task) for task in [0, tasks), each taken by the next free worker thread: for
/// tasks of uneven cost (blocks of a map with more or less in them). As with parallel_rows, each
/// task must write only its own outputs, so results do not depend on which thread ran it.
template <typename Body> void parallel_tasks(int tasks, const Body& body) {
    const int threads = std::min(worker_threads(), std::max(1, tasks));
    std::atomic<int> next{0};
    auto run = [&] {
        for (int t = next++; t < tasks; t = next++)
            body(t);
    };
    std::vector<std::thread> pool;
    pool.reserve(static_cast<std::size_t>(threads - 1));
    for (int t = 1; t < threads; ++t)
        pool.emplace_back(run);
    run();
    for (auto& th : pool)
        th.join();
}

} // namespace crackle
