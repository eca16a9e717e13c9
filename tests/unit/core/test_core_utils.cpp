#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json.hpp"
#include "core/strings.hpp"
#include "support/cli_runner.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <filesystem>
#include <random>

using namespace crackle;

TEST_SUITE("core") {
    TEST_CASE("strings: edit distance and did-you-mean suggestions") {
        CHECK(edit_distance("kitten", "sitting") == 3);
        CHECK(edit_distance("", "abc") == 3);
        CHECK(edit_distance("same", "same") == 0);
        const std::vector<std::string> keys = {"material.thickness", "material.toughness", "surface.size"};
        CHECK(closest_match("material.thicknes", keys) == "material.thickness");
        CHECK(closest_match("completely.different", keys).empty());
        CHECK(did_you_mean("surface.sise", keys) == " (did you mean 'surface.size'?)");
    }

    TEST_CASE("strings: the bounded did-you-mean search picks what exact distances pick") {
        // The reference: every distance exact, the first candidate at the smallest one, accepted
        // within a third of the word's length (at least 2).
        auto reference = [](const std::string& word, const std::vector<std::string>& candidates) {
            std::string best;
            std::size_t best_distance = std::string::npos;
            for (const auto& c : candidates)
                if (const std::size_t d = edit_distance(word, c); d < best_distance) {
                    best_distance = d;
                    best = c;
                }
            return best_distance <= std::max<std::size_t>(2, word.size() / 3) ? best : std::string();
        };
        std::mt19937_64 rng(16);
        auto random_word = [&](std::size_t max_length) {
            std::string w(rng() % (max_length + 1), 'a');
            for (char& c : w)
                c = "abc.d"[rng() % 5]; // a small alphabet: many near and equal distances
            return w;
        };
        std::size_t matched = 0;
        for (int trial = 0; trial < 2000; ++trial) {
            std::vector<std::string> candidates;
            for (int k = 0; k < 12; ++k)
                candidates.push_back(random_word(14));
            const std::string word = random_word(14);
            const std::string expected = reference(word, candidates);
            CAPTURE(word);
            REQUIRE(closest_match(word, candidates) == expected);
            matched += !expected.empty();
        }
        CHECK(matched > 200); // the comparison covered accepted matches, not only refusals
        CHECK(edit_distance("material.thickness", "material.toughness") == 4);
    }

    TEST_CASE("json: ordered objects and escaping and non-finite numbers") {
        Json j = Json::object();
        j["b"] = 1;
        j["a"] = "x\"y\n";
        j["c"] = std::nan("");
        Json arr = Json::array();
        arr.push_back(1.5);
        arr.push_back(true);
        j["d"] = arr;
        const std::string s = j.dump();
        CHECK(s.find("\"b\": 1") < s.find("\"a\"")); // insertion order kept
        CHECK(s.find("\"x\\\"y\\n\"") != std::string::npos);
        CHECK(s.find("\"c\": null") != std::string::npos);
        CHECK(s.find("1.5") != std::string::npos);
        CHECK(j.find("b")->as_number() == 1.0);
        CHECK(j.find("zzz") == nullptr);
    }

    TEST_CASE("atomic output: nothing appears until commit and nothing stays behind without it") {
        const auto dir = test::scratch_dir("atomic");
        {
            AtomicOutput out;
            out.write(dir / "a.txt", std::string_view("hello"));
            out.write(dir / "sub" / "b.txt", std::string_view("world"));
            CHECK_FALSE(std::filesystem::exists(dir / "a.txt"));
            out.commit();
        }
        CHECK(test::slurp(dir / "a.txt") == "hello");
        CHECK(test::slurp(dir / "sub" / "b.txt") == "world");
        {
            AtomicOutput out;
            out.write(dir / "c.txt", std::string_view("never"));
            // destroyed without commit, as when a later step throws
        }
        CHECK_FALSE(std::filesystem::exists(dir / "c.txt"));
        int leftovers = 0;
        for (const auto& e : std::filesystem::directory_iterator(dir))
            leftovers += e.path().string().find(".tmp") != std::string::npos;
        CHECK(leftovers == 0);
    }

    TEST_CASE("atomic output: an unwritable folder is an input error naming the path") {
        AtomicOutput out;
        CHECK_THROWS_AS(out.write("/proc/crackle-cannot-write-here/x.txt", std::string_view("x")), InputError);
    }

    TEST_CASE("CRACKLE_ASSERT throws with file and line and stays on in release builds") {
        bool thrown = false;
        try {
            CRACKLE_ASSERT(1 + 1 == 3, "arithmetic " << 42);
        } catch (const InvariantError& e) {
            thrown = true;
            const std::string what = e.what();
            CHECK(what.find("test_core_utils.cpp") != std::string::npos);
            CHECK(what.find("arithmetic 42") != std::string::npos);
        }
        CHECK(thrown);
    }
}
