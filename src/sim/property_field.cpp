#include "sim/property_field.hpp"

#include "core/error.hpp"
#include "core/rng.hpp"

namespace crackle::sim {

const char* to_string(PatternKind kind) {
    switch (kind) {
    case PatternKind::None:
        return "none";
    case PatternKind::Gradient:
        return "gradient";
    case PatternKind::Noise:
        return "noise";
    case PatternKind::Image:
        return "image";
    }
    return "?";
}

namespace {
constexpr int WAVES_PER_OCTAVE = 16;
}

SmoothNoise::SmoothNoise(const mesh::Surface& surface, double scale, int octaves, std::uint64_t seed)
    : m_periodic(surface.periodic()) {
    CRACKLE_ASSERT(scale > 0 && octaves >= 1, "noise scale and octaves must be positive");
    Rng rng(seed, RngStream::Material);
    double amplitude = 1.0, sum_sq = 0.0;
    for (int o = 0; o < octaves; ++o, scale *= 0.5, amplitude *= 0.5) {
        for (int w = 0; w < WAVES_PER_OCTAVE; ++w) {
            const double dir = TWO_PI * rng.uniform();
            const double phase = TWO_PI * rng.uniform();
            // Wavelength jittered ±25 % around the feature size.
            const double wavelength = scale * (0.75 + 0.5 * rng.uniform());
            Wave wave{Vec3::Zero(), phase, amplitude};
            if (m_periodic) {
                // Integer cycles per period keep the texture seamless.
                const Vec2 period = surface.period();
                double kx = std::round(std::cos(dir) * period.x() / wavelength);
                double ky = std::round(std::sin(dir) * period.y() / wavelength);
                if (kx == 0 && ky == 0) kx = 1;
                wave.k = Vec3(kx, ky, 0.0);
            } else {
                // Isotropic direction on the unit sphere.
                const double z = rng.uniform(-1.0, 1.0);
                const double s = safe_sqrt(1 - z * z);
                wave.k = (TWO_PI / wavelength) * Vec3(s * std::cos(dir), s * std::sin(dir), z);
            }
            m_waves.push_back(wave);
            sum_sq += 0.5 * sqr(amplitude);
        }
    }
    m_norm = std::sqrt(sum_sq); // standard deviation of the sum for random phases
}

double SmoothNoise::operator()(const Vec3& p, const Vec2& uv) const {
    double sum = 0;
    for (const Wave& w : m_waves) {
        const double arg = m_periodic ? TWO_PI * (w.k.x() * uv.x() + w.k.y() * uv.y()) : w.k.dot(p);
        sum += w.amplitude * std::cos(arg + w.phase);
    }
    // Roughly N(0, 1); ±3σ maps onto [0, 1].
    return clamp01(0.5 + sum / m_norm / 6.0);
}

PropertyField::PropertyField(double base, const VariationOptions& options, const mesh::Surface& surface,
                             std::uint64_t seed, std::uint64_t stream)
    : PropertyField(base, base, options, surface, seed, stream) {}

PropertyField::PropertyField(double base_start, double base_end, const VariationOptions& options,
                             const mesh::Surface& surface, std::uint64_t seed, std::uint64_t stream)
    : m_base(base_start), m_base_end(base_end), m_options(options), m_kind(surface.kind()) {
    switch (options.pattern) {
    case PatternKind::Noise:
        m_noise = std::make_unique<SmoothNoise>(surface, options.scale, options.octaves, seed * 7919 + stream);
        m_sample_size = options.scale * std::pow(0.5, options.octaves - 1) / 4.0;
        break;
    case PatternKind::Image: {
        CRACKLE_ASSERT(options.image && options.image->width > 0, "image pattern without an image");
        const Vec2 period = surface.period();
        m_sample_size = std::min(period.x() / options.image->width, period.y() / options.image->height);
        break;
    }
    case PatternKind::Gradient:
    case PatternKind::None:
        m_sample_size = 0.05 * std::min(surface.period().x(), surface.period().y());
        break;
    }
}

double PropertyField::pattern(const Vec3& p, const Vec2& uv) const {
    switch (m_options.pattern) {
    case PatternKind::None:
        return 0.5;
    case PatternKind::Gradient: {
        // Linear ramp across texture space along the direction, 0 at one corner, 1 at the other.
        const double th = m_options.angle_deg * DEG_TO_RAD;
        const double c = std::cos(th), s = std::sin(th);
        const double extent = std::abs(c) + std::abs(s);
        return clamp01(0.5 + ((uv.x() - 0.5) * c + (uv.y() - 0.5) * s) / extent);
    }
    case PatternKind::Noise:
        return (*m_noise)(p, uv);
    case PatternKind::Image: {
        // Image row 0 is the top of the texture (v = 1): the way it looks in a viewer.
        return m_options.image->sample_wrapped(uv.x(), 1.0 - uv.y());
    }
    }
    return 0.5;
}

double PropertyField::at(const Vec3& p, const Vec2& uv) const {
    const double v = m_base_end == m_base ? 0.0 : clamp01(uv.y() - std::floor(uv.y()));
    const double base = m_base + (m_base_end - m_base) * v;
    if (!varies()) return base;
    return base * (1.0 + m_options.amplitude * (2.0 * pattern(p, uv) - 1.0));
}

double PropertyField::min_value() const {
    const double a = varies() ? m_options.amplitude : 0.0;
    return std::min(m_base, m_base_end) * (1.0 - a);
}

double PropertyField::max_value() const {
    const double a = varies() ? m_options.amplitude : 0.0;
    return std::max(m_base, m_base_end) * (1.0 + a);
}

Vec2 face_point_uv(const mesh::SurfaceMesh& mesh, mesh::FaceId f, const mesh::Surface& surface, const Vec3& bary,
                   Vec3* position) {
    if (surface.periodic()) {
        const Vec2 d = bary[0] * mesh.corner_domain(f, 0) + bary[1] * mesh.corner_domain(f, 1)
                       + bary[2] * mesh.corner_domain(f, 2);
        if (position) *position = surface.position(d);
        // Unwrapped on purpose: u may pass 1 on a face across the border; samplers wrap.
        return Vec2(d.x() / surface.period().x(), d.y() / surface.period().y());
    }
    const auto pts = mesh.face_positions(f);
    const Vec3 p = surface.project(bary[0] * pts[0] + bary[1] * pts[1] + bary[2] * pts[2]);
    if (position) *position = p;
    return surface.uv(p);
}

double PropertyField::face_average(const mesh::SurfaceMesh& mesh, mesh::FaceId f, const mesh::Surface& surface) const {
    if (!varies() && m_base_end == m_base) return m_base;
    // Sub-triangles of the face: m × m per side, so each is smaller than the finest feature.
    const auto pts = mesh.face_positions(f);
    const double longest = std::max({(pts[1] - pts[0]).norm(), (pts[2] - pts[1]).norm(), (pts[0] - pts[2]).norm()});
    const int m = std::clamp(static_cast<int>(std::ceil(longest / m_sample_size)), 1, 32);
    double sum = 0;
    int count = 0;
    // Centroids of the m² sub-triangles of the regular subdivision (upward and downward ones).
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m - i; ++j) {
            for (int down = 0; down < 2; ++down) {
                if (down && j == m - i - 1) continue;
                const double a = down ? (i + 2.0 / 3.0) : (i + 1.0 / 3.0);
                const double b = down ? (j + 2.0 / 3.0) : (j + 1.0 / 3.0);
                const Vec3 bary(a / m, b / m, 1.0 - (a + b) / m);
                Vec3 p;
                const Vec2 uv = face_point_uv(mesh, f, surface, bary, &p);
                sum += at(p, uv);
                ++count;
            }
        }
    return sum / count;
}

} // namespace crackle::sim
