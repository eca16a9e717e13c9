#pragma once
/// @file Material properties that vary over the surface (Federl 2002, §5.9; digest §3.11):
/// thickness, Young's modulus, threshold stress and toughness, each a base value times a
/// pattern: p = p₀·(1 + a·(2g − 1)), g ∈ [0, 1] from a linear gradient, seeded smooth noise
/// or a grayscale image over texture space. An element takes the average over its area
/// ("the average of all pixels that map inside the element").

#include "core/image.hpp"
#include "core/math.hpp"
#include "mesh/surface.hpp"
#include "mesh/surface_mesh.hpp"

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace crackle::sim {

enum class PatternKind { None, Gradient, Noise, Image };

const char* to_string(PatternKind kind);

/// One [variation.<property>] preset section.
struct VariationOptions {
    PatternKind pattern = PatternKind::None;
    double amplitude = 0.3;                 ///< a: the property spans p₀·(1 − a) … p₀·(1 + a)
    double scale = 0.05;                    ///< noise feature size (m)
    int octaves = 3;                        ///< noise octaves, each half the size and amplitude of the last
    double angle_deg = 0.0;                 ///< gradient direction in texture space, degrees from u
    std::shared_ptr<const GrayImage> image; ///< image pattern (white = 1)
};

/// Smooth noise g ∈ [0, 1] that tiles: on periodic surfaces a sum of cosines with integer
/// wave numbers per period; on the sphere a sum of 3D plane waves. Deterministic in `seed`.
class SmoothNoise {
public:
    SmoothNoise(const mesh::Surface& surface, double scale, int octaves, std::uint64_t seed);
    /// @param p   3D point at t = 0 (used on the sphere)
    /// @param uv  texture coordinates (used on plane and cylinder)
    double operator()(const Vec3& p, const Vec2& uv) const;

private:
    struct Wave {
        Vec3 k; ///< plane: (kx, ky) in cycles per period; sphere: wave vector (rad/m)
        double phase, amplitude;
    };
    bool m_periodic;
    std::vector<Wave> m_waves;
    double m_norm = 1.0;
};

class PropertyField {
public:
    /// @param base     p₀ (unit of the property)
    /// @param seed     simulation seed; `stream` separates the properties' noise
    PropertyField(double base, const VariationOptions& options, const mesh::Surface& surface, std::uint64_t seed,
                  std::uint64_t stream);
    /// A base value that runs linearly along v, from `base_start` at v = 0 to `base_end` at
    /// v = 1 (the layer thickness of [material] thickness = [start, end], Fig. 5.29).
    PropertyField(double base_start, double base_end, const VariationOptions& options, const mesh::Surface& surface,
                  std::uint64_t seed, std::uint64_t stream);

    /// Pattern value g ∈ [0, 1] at a surface point (0.5 = no change).
    double pattern(const Vec3& p, const Vec2& uv) const;
    /// p₀(v)·(1 + a·(2g − 1))
    double at(const Vec3& p, const Vec2& uv) const;
    double base() const { return m_base; }
    /// Smallest and largest value the field can take.
    double min_value() const;
    double max_value() const;
    bool varies() const { return m_options.pattern != PatternKind::None && m_options.amplitude > 0; }

    /// Average over a face of a surface mesh, by sub-sampling the face finely enough to see
    /// every image pixel or noise feature inside it (at most 32 × 32 sub-triangles).
    double face_average(const mesh::SurfaceMesh& mesh, mesh::FaceId f, const mesh::Surface& surface) const;

private:
    double m_base;
    double m_base_end;
    VariationOptions m_options;
    mesh::SurfaceKind m_kind;
    std::unique_ptr<SmoothNoise> m_noise;
    double m_sample_size = 0; ///< finest feature (m) the averaging must resolve
};

/// Texture coordinates of a point on a face given by barycentric weights: interpolated in
/// the unrolled domain on periodic surfaces, projected onto the sphere otherwise.
Vec2 face_point_uv(const mesh::SurfaceMesh& mesh, mesh::FaceId f, const mesh::Surface& surface, const Vec3& bary,
                   Vec3* position = nullptr);

} // namespace crackle::sim
