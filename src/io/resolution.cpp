#include "io/resolution.hpp"

#include "core/math.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace crackle::io {

const ResolutionRule& resolution_rule() {
    static const ResolutionRule rule;
    return rule;
}

double surface_area(const Settings& s) {
    if (s.text("surface.kind") == "mesh")
        throw std::logic_error("surface_area: a model's area is its own (pass it to element_count)");
    const auto& size = s.numbers("surface.size");
    if (s.text("surface.kind") == "sphere") return 4 * PI * sqr(size[0]);
    return size[0] * (size.size() > 1 ? size[1] : size[0]);
}

Vec2 texture_tile(const Settings& s) {
    if (s.text("surface.kind") == "mesh") return Vec2(1.0, 1.0); // the model's UV square
    const auto& size = s.numbers("surface.size");
    if (s.text("surface.kind") == "sphere") return Vec2(TWO_PI * size[0], PI * size[0]);
    return Vec2(size[0], size.size() > 1 ? size[1] : size[0]);
}

MapSize map_size(const Settings& s) {
    return map_size(s, texture_tile(s));
}

MapSize map_size(const Settings& s, const Vec2& tile) {
    return map_request(s).on(tile);
}

MapSizeRequest map_request(const Settings& s) {
    return {static_cast<int>(s.integer("bake.size")), static_cast<int>(s.integer("bake.size_v"))};
}

MapSize MapSizeRequest::on(const Vec2& tile) const {
    if (rows > 0) return {size, rows};
    const double aspect = tile.y() / std::max(tile.x(), 1e-300); // v over u
    if (aspect <= 1.0) return {size, std::max(1, static_cast<int>(std::lround(size * aspect)))};
    return {std::max(1, static_cast<int>(std::lround(size / aspect))), size};
}

std::int64_t minimum_elements(const Settings& s) {
    const std::string& kind = s.text("surface.kind");
    if (kind == "plane" || kind == "mesh") return 0; // a model's curvature: its remeshing keeps it
    // A triangle spanning more than a sixth of the way around turns its wedge inside out.
    const auto& size = s.numbers("surface.size");
    const double around = kind == "sphere" ? 2 * PI * size[0] : size[0];
    const double edge = around / 6.0;
    return static_cast<std::int64_t>(std::ceil(surface_area(s) / (std::sqrt(3.0) / 4.0 * sqr(edge))));
}

namespace {

/// The thickness h whose square sets the element count: the thinnest the layer gets on a uniform
/// mesh (the smaller end of the ramp, lowered by a variation); with simulation.density =
/// "thickness" the mesh follows the thickness, so the count is the area integral of 1/h², and for
/// the linear ramp from t₀ to t₁ the mean of 1/h² is 1/(t₀·t₁).
double resolving_thickness(const Settings& s) {
    const auto& t = s.numbers("material.thickness");
    const double t0 = t.front(), t1 = t.back();
    const double lowered =
        s.text("variation.thickness.pattern") != "none" ? 1.0 - s.number("variation.thickness.amplitude") : 1.0;
    if (s.text("simulation.density") == "thickness") return std::sqrt(t0 * t1) * lowered;
    return std::min(t0, t1) * lowered;
}

} // namespace

ElementCount element_count(const Settings& s, bool preview, double model_area) {
    const ResolutionRule& rule = resolution_rule();
    const double h = resolving_thickness(s), area = model_area > 0 ? model_area : surface_area(s);
    const double q = preview ? rule.preview_elements_per_thickness_squared : s.number("simulation.elements_per_h2");
    const MapSize map = map_size(s);
    const double cap = map.pixels() / rule.pixels_per_element;
    ElementCount out;
    if (!s.is_auto("simulation.elements")) {
        out.elements = s.integer("simulation.elements");
        if (!preview) return out;
    }
    const double wanted = h > 0 ? q * area / sqr(h) : double(rule.min_elements);
    const double floor = double(std::max<std::int64_t>(rule.min_elements, minimum_elements(s)));
    const double n = std::clamp(std::min(wanted, cap), floor, 2.0e6);
    const auto count = static_cast<std::int64_t>(std::llround(n));
    char buf[320];
    int len = std::snprintf(buf, sizeof buf, "%s%.3g elements per h² over %.3g m² (h = %.3g m) = %.0f",
                            preview ? "preview: " : "", q, area, h, wanted);
    if (wanted > cap && n < wanted) {
        len += std::snprintf(buf + len, sizeof buf - std::size_t(len), ", capped at %lld for a %d",
                             static_cast<long long>(count), map.width);
        if (map.height != map.width) len += std::snprintf(buf + len, sizeof buf - std::size_t(len), "x%d", map.height);
        len += std::snprintf(buf + len, sizeof buf - std::size_t(len), " px texture");
    } else if (n > wanted)
        std::snprintf(buf + len, sizeof buf - std::size_t(len), ", raised to %lld (%s)", static_cast<long long>(count),
                      floor > double(rule.min_elements) ? "the curved surface's minimum" : "the smallest model");
    if (out.elements > 0 && out.elements <= count) return out; // an explicit count already coarser
    out.elements = count;
    out.automatic = true;
    out.reason = buf;
    return out;
}

} // namespace crackle::io
