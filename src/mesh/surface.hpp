#pragma once
/// @file The three surfaces crackle grows (Federl 2002, Ch. 3): a periodic plane, a cylinder
/// (tree trunk) periodic around and along its axis, and a closed sphere. Each maps to texture
/// space (u, v) ∈ [0, 1)² and has positions, outward normals and a local tangent frame.
///
/// Plane and cylinder use *domain coordinates* (x, y) ∈ [0, Lx) × [0, Ly): x along u and
/// y along v, in metres. On the cylinder x is arc length around the trunk (the cylinder is
/// developable, so distances in the domain are surface distances). Both are tori in
/// parameter space, so every texture baked from them tiles.

#include "core/math.hpp"

#include <memory>

namespace crackle::mesh {

class ModelSurface;

/// The three analytic surfaces, and the artist's own model (issue 30: a closed or open triangle
/// mesh with its own UV layout, mesh/model_surface.hpp).
enum class SurfaceKind { Plane, Cylinder, Sphere, Mesh };

const char* to_string(SurfaceKind kind);

/// Parameters of the [surface] preset section.
struct SurfaceOptions {
    SurfaceKind kind = SurfaceKind::Cylinder;
    /// plane: [width, height] m; cylinder: [circumference, height] m; sphere: [radius, unused] m
    Vec2 size = Vec2(0.5, 0.5);
    /// The model of SurfaceKind::Mesh (read by io::read_model); its size is the model's own.
    std::shared_ptr<const ModelSurface> model;
    bool operator==(const SurfaceOptions&) const = default; ///< every field: the options test compares whole structs
};

/// Local orthonormal frame at a surface point: e_u and e_v span the tangent plane
/// (along increasing u and v), n is the outward normal.
struct TangentFrame {
    Vec3 e_u, e_v, n;
};

class Surface {
public:
    explicit Surface(const SurfaceOptions& options);

    SurfaceKind kind() const { return m_kind; }
    bool periodic() const { return m_kind == SurfaceKind::Plane || m_kind == SurfaceKind::Cylinder; }
    /// The artist's model (SurfaceKind::Mesh), else nullptr.
    const ModelSurface* model() const { return m_model.get(); }

    /// Domain size (Lx, Ly) of a periodic surface in metres.
    Vec2 period() const { return m_period; }
    double radius() const { return m_radius; } ///< cylinder / sphere radius
    double area() const;

    // === Periodic surfaces: domain coordinates → 3D (background at t = 0)
    Vec3 position(const Vec2& domain) const;
    TangentFrame frame(const Vec2& domain) const;
    Vec2 uv_of_domain(const Vec2& domain) const;

    /// The 3D translation that identifies copies across the periodic borders at t = 0:
    /// plane (ox·W, oy·H, 0); cylinder (0, 0, oy·H), since going around wraps by itself.
    Vec3 period_shift(const Vec2i& offset) const;

    // === Any surface: 3D points on the surface
    /// Outward unit normal at a point on (or near) the surface.
    Vec3 normal(const Vec3& p) const;
    TangentFrame frame(const Vec3& p) const;
    /// Texture coordinates of a point: sphere u = longitude/2π, v = 1 − colatitude/π
    /// (equirectangular: v = 1 at the north pole +z, v = 0 at the south pole).
    Vec2 uv(const Vec3& p) const;
    /// Closest point on the surface (sphere: radial projection).
    Vec3 project(const Vec3& p) const;

private:
    SurfaceKind m_kind;
    Vec2 m_period;
    double m_radius = 0.0;
    std::shared_ptr<const ModelSurface> m_model;
};

} // namespace crackle::mesh
