#include "core/log.hpp"
#include "core/parallel.hpp"
#include "core/timer.hpp"
#include "render/relief.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::render {

Relief shape_relief_curves(const RasterLayers& layers, const std::vector<CrackCurve>& curves, const ReliefOptions& o) {
    const PixelGrid& g = layers.grid;
    const std::size_t px = g.pixels();
    Relief out;
    out.height.assign(px, 0.0f);
    out.groove.assign(px, 0.0f);

    Timer timer;
    // === 1. The plates' height, smoothed over about a third of an element and continued across
    // the cracks (the grooves are cut into it below, from the crack curves).
    std::vector<std::uint8_t> plate(px);
    parallel_rows(g.height, [&](int y) {
        for (std::size_t i = g.index(0, y), end = i + std::size_t(g.width); i < end; ++i)
            plate[i] = !layers.crack[i];
    });
    const double sigma_px = o.element_size > 0 ? 0.35 * o.element_size / g.metres_v : 0.0;
    const PlateHeights plates = plate_heights(layers, plate, sigma_px);
    std::vector<float> top = smooth_plates(g, plates, sigma_px);
    // Inside the cracks the plates' height is continued smoothly from both sides (a wider
    // blur, blended in over the smoothing's reach), so the grooves cut into a smooth surface;
    // only gaps wider than that take the nearest plate's height.
    if (std::find(plate.begin(), plate.end(), 1) != plate.end()) {
        const DistanceField near = distance_transform(g, plate, true);
        const double reach = std::max(1.5, sigma_px) * g.metres_v;
        const std::vector<float> wide = smooth_plates(g, plates, 3.0 * std::max(sigma_px, 2.0));
        parallel_rows(g.height, [&](int y) { // (a crack pixel's nearest plate pixel keeps its height)
            for (std::size_t i = g.index(0, y), end = i + std::size_t(g.width); i < end; ++i) {
                if (plate[i]) continue;
                const double w = std::clamp(near.distance[i] / reach, 0.0, 1.0);
                const double fill = wide[i] > 0 ? wide[i] : top[near.nearest[i]];
                top[i] = static_cast<float>((1 - w * w * (3 - 2 * w)) * top[i] + w * w * (3 - 2 * w) * fill);
            }
        });
    }
    const double t_top = timer.seconds();

    // === 2-3. Grooves and curl from the distance to the crack curves (render/groove.hpp).
    GrooveOptions go;
    go.crack_width = o.crack_width;
    go.crack_depth = o.crack_depth;
    go.bevel = o.bevel;
    go.crack_shape = o.crack_shape;
    go.rounding = std::max(o.bevel, 1.5 * std::max(g.metres_v, g.metres_u[static_cast<std::size_t>(g.height / 2)]));
    go.curl = o.curl;
    go.smoothing_px = std::max(2.0, sigma_px);
    go.pixel = std::max(g.metres_v, g.metres_u[static_cast<std::size_t>(g.height / 2)]);
    // The shapes are sized for a map of bake.shape_size pixels across u, so a groove keeps its
    // shape in metres at every map size (finer maps are smoother per pixel, coarser ones crisper).
    go.shape_pixel = go.pixel * g.width / std::max(o.shape_size, 1);
    go.join_radius = 6.0 * go.shape_pixel;
    double mean_top = 0;
    for (float h : top)
        mean_top += h;
    go.curl_reach = o.curl_width * mean_top / double(std::max<std::size_t>(px, 1));
    GrooveField grooves = groove_field(g, curves, top, go);
    const double t_grooves = timer.seconds();
    const Detail detail = micro_relief(g, DetailOptions{o.fibre, o.flake, o.grit, o.seed});
    const double t_detail = timer.seconds();
    const double detail_depth = o.fibre.depth + o.flake.depth + o.grit.depth;
    out.flake = detail.flake;
    out.detail.assign(px, 0.0f);
    out.coverage = std::move(grooves.coverage);
    out.age = std::move(grooves.age);
    parallel_rows(g.height, [&](int y) {
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = g.index(x, y);
            const double t = top[i], lift = grooves.lift[i], drop = grooves.drop[i];
            // The groove is cut from the lifted rim down to the ground: at full depth (drop = top)
            // the height is 0 whatever the lift.
            double h = t > 0 ? t + lift - drop * (1.0 + lift / t) : 0.0;
            out.groove[i] = static_cast<float>(t > 0 ? std::clamp(drop / t, 0.0, 1.0) : 0.0);
            // === 4. Micro-relief, attenuated near the ground so heights stay ≥ 0.
            if (detail_depth > 0) {
                out.detail[i] = static_cast<float>(detail.height[i] / detail_depth);
                h += detail.height[i] * std::min(1.0, std::max(h, 0.0) / detail_depth);
            }
            out.height[i] = static_cast<float>(std::max(0.0, h));
        }
    });
    log::debug("relief: plate tops ", t_top, " s, grooves ", t_grooves - t_top, " s (", curves.size(),
               " curves), micro-relief ", t_detail - t_grooves, " s, profile ", timer.seconds() - t_detail, " s");
    return out;
}

void relabel_cracks(RasterLayers& layers, const Relief& relief) {
    const PixelGrid& g = layers.grid;
    const std::size_t px = g.pixels();
    std::vector<std::uint8_t> crack(px), source(px);
    parallel_rows(g.height, [&](int y) {
        for (std::size_t i = g.index(0, y), end = i + std::size_t(g.width); i < end; ++i) {
            crack[i] = relief.coverage[i] >= 0.5f || relief.groove[i] >= 0.5f;
            source[i] = !crack[i] && layers.label[i] >= 0;
        }
    });
    if (std::find(source.begin(), source.end(), 1) == source.end()) {
        layers.crack = std::move(crack);
        return;
    }
    const DistanceField near = distance_transform(g, source, true);
    // (A source pixel keeps its label and colour: the rows can be relabelled in any order.)
    parallel_rows(g.height, [&](int y) {
        for (std::size_t i = g.index(0, y), end = i + std::size_t(g.width); i < end; ++i) {
            if (crack[i]) {
                layers.label[i] = -1;
            } else if (layers.label[i] < 0) {
                const std::size_t j = near.nearest[i];
                layers.label[i] = layers.label[j];
                for (std::size_t c = 0; c < 3; ++c)
                    layers.id[3 * i + c] = layers.id[3 * j + c];
            }
        }
    });
    layers.crack = std::move(crack);
}

} // namespace crackle::render
