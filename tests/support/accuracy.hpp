#pragma once
/// @file The measured side of docs/accuracy.md: a test that checks one of the thesis' claims
/// records what it measured, next to the tolerance its CHECK enforces. scripts/accuracy runs
/// the suite with CRACKLE_ACCURACY_LOG set and turns the records into the table; without the
/// variable this does nothing. The CHECK, not the record, is what makes a test fail.

#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <sstream>
#include <string>

namespace crackle::test {

/// Appends one record: figure or claim id (e.g. "5.21"), the claim in a few words, what was
/// measured, its value, and the tolerance as the test states it (e.g. "< 0.03 m").
inline void record_claim(const std::string& id, const std::string& claim, const std::string& measured, double value,
                         const std::string& tolerance) {
    const char* path = std::getenv("CRACKLE_ACCURACY_LOG");
    if (!path || !*path) return;
    static std::mutex mutex;
    const std::lock_guard<std::mutex> lock(mutex);
    std::FILE* out = std::fopen(path, "a");
    if (!out) return;
    const doctest::ContextOptions* ctx = doctest::getContextOptions();
    const std::string test = ctx && ctx->currentTest ? ctx->currentTest->m_name : "?";
    std::ostringstream value_text;
    value_text.precision(4);
    value_text << value;
    auto clean = [](std::string s) {
        for (char& c : s)
            if (c == '\t' || c == '\n') c = ' ';
        return s;
    };
    std::fprintf(out, "%s\t%s\t%s\t%s\t%s\t%s\n", clean(id).c_str(), clean(claim).c_str(), clean(test).c_str(),
                 clean(measured).c_str(), value_text.str().c_str(), clean(tolerance).c_str());
    std::fclose(out);
}

} // namespace crackle::test
