#include "fracture/preview.hpp"

#include <array>

namespace crackle::fracture {

namespace {

std::array<std::uint8_t, 3> fragment_colour(int label) {
    // A hash spread over pale hues, so neighbouring fragments differ.
    std::uint32_t h = static_cast<std::uint32_t>(label) * 2654435761u;
    h ^= h >> 15;
    const auto c = [&](int shift) { return static_cast<std::uint8_t>(140 + ((h >> shift) & 0x5f)); };
    return {c(0), c(8), c(16)};
}

void fill_triangle(RgbImage& img, const std::array<Vec2, 3>& uv, const std::array<std::uint8_t, 3>& colour) {
    const double W = img.width, H = img.height;
    // Pixel space: x = u·W, y = (1 − v)·H.
    std::array<Vec2, 3> p;
    for (std::size_t k = 0; k < 3; ++k)
        p[k] = Vec2(uv[k].x() * W, (1.0 - uv[k].y()) * H);
    const double area = (p[1] - p[0]).x() * (p[2] - p[0]).y() - (p[2] - p[0]).x() * (p[1] - p[0]).y();
    if (std::abs(area) < 1e-12) return;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].x(), p[1].x(), p[2].x()}))));
    const int x1 = std::min(img.width - 1, static_cast<int>(std::ceil(std::max({p[0].x(), p[1].x(), p[2].x()}))));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({p[0].y(), p[1].y(), p[2].y()}))));
    const int y1 = std::min(img.height - 1, static_cast<int>(std::ceil(std::max({p[0].y(), p[1].y(), p[2].y()}))));
    for (int y = y0; y <= y1; ++y)
        for (int x = x0; x <= x1; ++x) {
            const Vec2 c(x + 0.5, y + 0.5);
            double w[3];
            for (std::size_t k = 0; k < 3; ++k) {
                const Vec2& a = p[(k + 1) % 3];
                const Vec2& b = p[(k + 2) % 3];
                w[k] = ((b - a).x() * (c - a).y() - (c - a).x() * (b - a).y()) / area;
            }
            if (w[0] < 0 || w[1] < 0 || w[2] < 0) continue;
            std::uint8_t* px = &img.pixels[3
                                           * (static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width)
                                              + static_cast<std::size_t>(x))];
            px[0] = colour[0];
            px[1] = colour[1];
            px[2] = colour[2];
        }
}

void draw_line(RgbImage& img, const Vec2& a_uv, const Vec2& b_uv, const std::array<std::uint8_t, 3>& colour) {
    const Vec2 a(a_uv.x() * img.width, (1.0 - a_uv.y()) * img.height);
    const Vec2 b(b_uv.x() * img.width, (1.0 - b_uv.y()) * img.height);
    const int steps = std::max(1, static_cast<int>(std::ceil(2.0 * (b - a).lpNorm<Eigen::Infinity>())));
    for (int i = 0; i <= steps; ++i) {
        const Vec2 q = a + (b - a) * (static_cast<double>(i) / steps);
        const int x = static_cast<int>(std::floor(q.x())), y = static_cast<int>(std::floor(q.y()));
        if (x < 0 || y < 0 || x >= img.width || y >= img.height) continue;
        std::uint8_t* px = &img.pixels[3
                                       * (static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width)
                                          + static_cast<std::size_t>(x))];
        px[0] = colour[0];
        px[1] = colour[1];
        px[2] = colour[2];
    }
}

/// Texture coordinates of a face's corners, unwrapped so the triangle is contiguous.
std::array<Vec2, 3> face_uv(const CrackPattern& p, mesh::FaceId f) {
    std::array<Vec2, 3> uv;
    if (p.surface.periodic()) {
        for (int k = 0; k < 3; ++k) {
            const Vec2 d = p.mesh.corner_domain(f, k);
            uv[static_cast<std::size_t>(k)] = Vec2(d.x() / p.mesh.period.x(), d.y() / p.mesh.period.y());
        }
    } else {
        for (int k = 0; k < 3; ++k)
            uv[static_cast<std::size_t>(k)] = p.surface.uv(p.mesh.corner_position(f, k));
        for (std::size_t k = 1; k < 3; ++k) { // unwrap across the date line
            if (uv[k].x() - uv[0].x() > 0.5) uv[k].x() -= 1.0;
            if (uv[k].x() - uv[0].x() < -0.5) uv[k].x() += 1.0;
        }
    }
    const Vec2 base(std::floor(uv[0].x()), std::floor(uv[0].y()));
    for (auto& q : uv)
        q -= base;
    return uv;
}

} // namespace

RgbImage preview_image(const CrackPattern& p, int size) {
    RgbImage img;
    img.width = img.height = size;
    img.pixels.assign(3 * static_cast<std::size_t>(size) * static_cast<std::size_t>(size), 20);
    for (std::size_t fi = 0; fi < p.mesh.num_faces(); ++fi) {
        const auto f = mesh::face_id(fi);
        const std::array<Vec2, 3> uv = face_uv(p, f);
        const auto colour = p.removed[fi] ? std::array<std::uint8_t, 3>{25, 20, 18} : fragment_colour(p.fragment[fi]);
        // Draw the triangle and its wrapped copies.
        const int dv_max = p.surface.periodic() ? 1 : 0;
        for (int du = -1; du <= 1; ++du)
            for (int dv = -dv_max; dv <= dv_max; ++dv) {
                std::array<Vec2, 3> s = uv;
                for (auto& q : s)
                    q += Vec2(du, dv);
                fill_triangle(img, s, colour);
            }
    }
    // Crack lips that are not bounded by removed elements (splitting, broken springs).
    const int dv_max = p.surface.periodic() ? 1 : 0;
    for (const CrackEdge& c : p.cracks) {
        const std::array<Vec2, 3> uv = face_uv(p, c.face);
        const Vec2 a = uv[static_cast<std::size_t>(c.edge)], b = uv[static_cast<std::size_t>((c.edge + 1) % 3)];
        for (int du = -1; du <= 1; ++du)
            for (int dv = -dv_max; dv <= dv_max; ++dv)
                draw_line(img, a + Vec2(du, dv), b + Vec2(du, dv), {25, 20, 18});
    }
    return img;
}

} // namespace crackle::fracture
