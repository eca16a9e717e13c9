#include "core/strings.hpp"

#include <algorithm>
#include <numeric>

namespace crackle {

namespace {

/// Levenshtein distance of a and b, or `cap` + 1 as soon as it must exceed `cap` (a row of the
/// table never decreases its minimum). The two rows are the caller's, so a search over many
/// candidates allocates once.
std::size_t bounded_edit_distance(std::string_view a, std::string_view b, std::size_t cap,
                                  std::vector<std::size_t>& prev, std::vector<std::size_t>& cur) {
    if ((a.size() > b.size() ? a.size() - b.size() : b.size() - a.size()) > cap) return cap + 1;
    prev.resize(b.size() + 1);
    cur.resize(b.size() + 1);
    std::iota(prev.begin(), prev.end(), std::size_t{0});
    for (std::size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        std::size_t row_min = cur[0];
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t subst = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, subst});
            row_min = std::min(row_min, cur[j]);
        }
        if (row_min > cap) return cap + 1;
        std::swap(prev, cur);
    }
    return std::min(prev[b.size()], cap + 1);
}

} // namespace

std::size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> prev, cur;
    return bounded_edit_distance(a, b, std::max(a.size(), b.size()), prev, cur);
}

std::string closest_match(std::string_view word, const std::vector<std::string>& candidates) {
    // Accept up to a third of the word's length in edits (at least 2). Distances past that
    // limit are only ever refused, so the search stops counting there: the first candidate at
    // the smallest distance is the same as with exact distances.
    const std::size_t limit = std::max<std::size_t>(2, word.size() / 3);
    std::vector<std::size_t> prev, cur;
    const std::string* best = nullptr;
    std::size_t best_distance = limit + 1;
    for (const auto& c : candidates) {
        const std::size_t d = bounded_edit_distance(word, c, std::min(limit, best_distance), prev, cur);
        if (d < best_distance) {
            best_distance = d;
            best = &c;
        }
    }
    return best ? *best : std::string();
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
    const std::string m = closest_match(word, candidates);
    return m.empty() ? std::string() : " (did you mean '" + m + "'?)";
}

std::vector<std::string> split(std::string_view text, char separator) {
    std::vector<std::string> parts;
    if (text.empty()) return parts;
    std::size_t start = 0;
    while (true) {
        const std::size_t end = text.find(separator, start);
        parts.emplace_back(text.substr(start, end == std::string_view::npos ? text.size() - start : end - start));
        if (end == std::string_view::npos) return parts;
        start = end + 1;
    }
}

std::string trim(std::string_view text) {
    const std::size_t a = text.find_first_not_of(" \t");
    if (a == std::string_view::npos) return "";
    const std::size_t b = text.find_last_not_of(" \t");
    return std::string(text.substr(a, b - a + 1));
}

std::string hex64(std::uint64_t value) {
    static const char* digits = "0123456789abcdef";
    std::string s(16, '0');
    for (int i = 15; i >= 0; --i, value >>= 4)
        s[static_cast<std::size_t>(i)] = digits[value & 15];
    return s;
}

std::string join(const std::vector<std::string>& parts, std::string_view separator) {
    std::string out;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        if (i > 0) out += separator;
        out += parts[i];
    }
    return out;
}

} // namespace crackle
