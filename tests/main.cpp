// doctest main, in its own translation unit (it is slow to compile and rarely changes).
#define DOCTEST_CONFIG_IMPLEMENT
#include "core/parallel.hpp"

#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

/// With CRACKLE_ACCURACY_LOG set, appends "#ran <TAB> test <TAB> passed|failed" to that log when a
/// test case ends, beside the records of test::record_claim (tests/support/accuracy.hpp): the
/// ctest check of docs/accuracy.md (scripts/accuracy-check) judges the tests that ran. Three
/// fields, so scripts/accuracy, which reads lines of six, skips them.
class RanListener : public doctest::IReporter {
public:
    explicit RanListener(const doctest::ContextOptions&) {}
    void report_query(const doctest::QueryData&) override {}
    void test_run_start() override {}
    void test_run_end(const doctest::TestRunStats&) override {}
    void test_case_start(const doctest::TestCaseData& data) override { m_test = data.m_name; }
    void test_case_reenter(const doctest::TestCaseData&) override {}
    void test_case_end(const doctest::CurrentTestCaseStats& stats) override {
        const char* path = std::getenv("CRACKLE_ACCURACY_LOG");
        if (!path || !*path) return;
        std::FILE* out = std::fopen(path, "a");
        if (!out) return;
        for (char& c : m_test)
            if (c == '\t' || c == '\n') c = ' ';
        std::fprintf(out, "#ran\t%s\t%s\n", m_test.c_str(), stats.testCaseSuccess ? "passed" : "failed");
        std::fclose(out);
    }
    void test_case_exception(const doctest::TestCaseException&) override {}
    void subcase_start(const doctest::SubcaseSignature&) override {}
    void subcase_end() override {}
    void log_assert(const doctest::AssertData&) override {}
    void log_message(const doctest::MessageData&) override {}
    void test_case_skipped(const doctest::TestCaseData&) override {}

private:
    std::string m_test;
};

} // namespace

REGISTER_LISTENER("accuracy-ran", 1, RanListener);

int main(int argc, char** argv) {
    // Tests are hermetic: no pattern cache in the user's home folder, and no test served a
    // pattern another test simulated. The cache's own tests point CRACKLE_CACHE at a scratch folder.
    setenv("CRACKLE_CACHE", "off", 1);
    crackle::pin_blas_threads(); // as the CLI does: the same sums on every machine

    return doctest::Context(argc, argv).run();
}
