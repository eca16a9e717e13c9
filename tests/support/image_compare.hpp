#pragma once
/// @file Comparing images with tolerances (style guide §8): MAE, RMSE, max and the share of
/// pixels within tolerance; on failure the actual, reference and a diff heat-map go to
/// ${build}/test-output/ (Mitsuba's error_output).

#include "core/atomic_file.hpp"
#include "io/png.hpp"
#include "support/cli_runner.hpp"

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace crackle::test {

struct ImageComparison {
    double mae = 0, rmse = 0, max = 0;
    double within = 0; ///< share of pixels whose error ≤ tolerance
    std::string report() const {
        return "MAE " + std::to_string(mae) + ", RMSE " + std::to_string(rmse) + ", max " + std::to_string(max)
               + ", within tolerance " + std::to_string(100.0 * within) + " %";
    }
};

/// Per-pixel errors of two equally sized pixel arrays (`error` gives one pixel's error).
template <typename Error>
ImageComparison compare_pixels(std::size_t pixels, double tolerance, Error error,
                               std::vector<float>* errors = nullptr) {
    ImageComparison c;
    std::size_t ok = 0;
    double sum = 0, sum2 = 0;
    if (errors) errors->resize(pixels);
    for (std::size_t i = 0; i < pixels; ++i) {
        const double e = error(i);
        sum += e;
        sum2 += e * e;
        c.max = std::max(c.max, e);
        ok += e <= tolerance;
        if (errors) (*errors)[i] = static_cast<float>(e);
    }
    c.mae = sum / double(pixels);
    c.rmse = std::sqrt(sum2 / double(pixels));
    c.within = double(ok) / double(pixels);
    return c;
}

/// Writes actual, reference and a heat-map of the errors (scaled to `scale`) for a failed comparison.
inline std::string write_failure(const std::string& name, const std::vector<std::uint8_t>& actual_png,
                                 const std::vector<std::uint8_t>& reference_png, const std::vector<float>& errors,
                                 int width, double scale) {
    const auto dir =
        std::filesystem::path(std::getenv("CRACKLE_TEST_OUTPUT") ? std::getenv("CRACKLE_TEST_OUTPUT") : "/tmp")
        / "golden-failures";
    std::vector<std::uint8_t> heat(3 * errors.size());
    for (std::size_t i = 0; i < errors.size(); ++i) {
        const double t = std::min(1.0, errors[i] / scale);
        heat[3 * i] = static_cast<std::uint8_t>(255 * t);
        heat[3 * i + 1] = static_cast<std::uint8_t>(255 * (1 - std::abs(2 * t - 1)));
        heat[3 * i + 2] = static_cast<std::uint8_t>(255 * (1 - t));
    }
    auto bytes = [](const std::vector<std::uint8_t>& v) {
        return std::string_view(reinterpret_cast<const char*>(v.data()), v.size());
    };
    write_file_atomically(dir / (name + "_actual.png"), bytes(actual_png));
    write_file_atomically(dir / (name + "_reference.png"), bytes(reference_png));
    write_file_atomically(dir / (name + "_diff.png"),
                          bytes(io::encode_png_rgb8(width, static_cast<int>(errors.size()) / width, 3, heat)));
    return (dir / name).string() + "_{actual,reference,diff}.png";
}

} // namespace crackle::test
