#include "mesh/surface.hpp"

#include "core/error.hpp"
#include "mesh/model_surface.hpp"

namespace crackle::mesh {

const char* to_string(SurfaceKind kind) {
    switch (kind) {
    case SurfaceKind::Plane:
        return "plane";
    case SurfaceKind::Cylinder:
        return "cylinder";
    case SurfaceKind::Sphere:
        return "sphere";
    case SurfaceKind::Mesh:
        return "mesh";
    }
    return "?";
}

namespace {

/// A model's tangent frame at a point: e_u along its UV layout's u where it has one (bark laid
/// out around the trunk grows around it), else along the projected x axis; n the smooth normal.
TangentFrame model_frame(const ModelSurface& model, const Vec3& p) {
    const ModelSurface::Hit hit = model.closest(p);
    const Vec3 n = model.normal(hit);
    Vec3 u = Vec3::Zero();
    if (model.has_uv()) {
        // ∂position/∂u of the hit's triangle: solve the 2×2 system of its UV edges.
        const auto& t = model.model().triangles[static_cast<std::size_t>(hit.triangle)];
        const auto& uv = model.model().corner_uv[static_cast<std::size_t>(hit.triangle)];
        const Vec3& a = model.model().positions[static_cast<std::size_t>(t[0])];
        const Vec3 e1 = model.model().positions[static_cast<std::size_t>(t[1])] - a;
        const Vec3 e2 = model.model().positions[static_cast<std::size_t>(t[2])] - a;
        const Vec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
        const double det = d1.x() * d2.y() - d2.x() * d1.y();
        if (std::abs(det) > 1e-300) u = (e1 * d2.y() - e2 * d1.y()) / det;
    }
    u -= u.dot(n) * n;
    if (u.norm() < 1e-12 * std::max(1.0, p.norm())) {
        u = Vec3::UnitX() - n.x() * n;
        if (u.norm() < 1e-6) u = Vec3::UnitY() - n.y() * n;
    }
    u.normalize();
    return {u, n.cross(u), n};
}

} // namespace

Surface::Surface(const SurfaceOptions& options) : m_kind(options.kind) {
    CRACKLE_ASSERT(options.size.x() > 0, "surface size must be positive");
    switch (m_kind) {
    case SurfaceKind::Plane:
        m_period = options.size;
        break;
    case SurfaceKind::Cylinder:
        m_period = options.size;
        m_radius = options.size.x() / TWO_PI;
        break;
    case SurfaceKind::Sphere:
        m_radius = options.size.x();
        m_period = Vec2(TWO_PI * m_radius, PI * m_radius);
        break;
    case SurfaceKind::Mesh:
        CRACKLE_ASSERT(options.model != nullptr, "a mesh surface needs its model");
        m_model = options.model;
        // The model's UV square: a nominal tile of its area (texel density varies over a model).
        m_period = Vec2::Constant(std::sqrt(m_model->area()));
        break;
    }
}

double Surface::area() const {
    if (m_kind == SurfaceKind::Sphere) return 4.0 * PI * sqr(m_radius);
    if (m_kind == SurfaceKind::Mesh) return m_model->area();
    return m_period.x() * m_period.y();
}

Vec3 Surface::position(const Vec2& d) const {
    switch (m_kind) {
    case SurfaceKind::Plane:
        return Vec3(d.x(), d.y(), 0.0);
    case SurfaceKind::Cylinder: {
        // Federl 2002, Eq. 3.5: the trunk axis is z; x is arc length around it.
        const double phi = d.x() / m_radius;
        return Vec3(m_radius * std::cos(phi), m_radius * std::sin(phi), d.y());
    }
    case SurfaceKind::Sphere:
    case SurfaceKind::Mesh:
        break;
    }
    CRACKLE_ASSERT(false, "domain coordinates are only defined on periodic surfaces");
}

TangentFrame Surface::frame(const Vec2& d) const {
    if (m_kind == SurfaceKind::Plane) return {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
    return frame(position(d));
}

Vec2 Surface::uv_of_domain(const Vec2& d) const {
    return Vec2(wrap(d.x() / m_period.x(), 1.0), wrap(d.y() / m_period.y(), 1.0));
}

Vec3 Surface::period_shift(const Vec2i& o) const {
    switch (m_kind) {
    case SurfaceKind::Plane:
        return Vec3(o.x() * m_period.x(), o.y() * m_period.y(), 0.0);
    case SurfaceKind::Cylinder:
        return Vec3(0.0, 0.0, o.y() * m_period.y());
    case SurfaceKind::Sphere:
    case SurfaceKind::Mesh:
        return Vec3::Zero();
    }
    return Vec3::Zero();
}

Vec3 Surface::normal(const Vec3& p) const {
    switch (m_kind) {
    case SurfaceKind::Plane:
        return Vec3::UnitZ();
    case SurfaceKind::Cylinder: {
        const Vec2 r(p.x(), p.y());
        const double len = r.norm();
        return len > 0 ? Vec3(r.x() / len, r.y() / len, 0.0) : Vec3::UnitX();
    }
    case SurfaceKind::Sphere: {
        const double len = p.norm();
        return len > 0 ? Vec3(p / len) : Vec3::UnitZ();
    }
    case SurfaceKind::Mesh:
        return m_model->normal(m_model->closest(p));
    }
    return Vec3::UnitZ();
}

TangentFrame Surface::frame(const Vec3& p) const {
    switch (m_kind) {
    case SurfaceKind::Plane:
        return {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
    case SurfaceKind::Cylinder: {
        const Vec3 n = normal(p);
        return {Vec3(-n.y(), n.x(), 0.0), Vec3::UnitZ(), n};
    }
    case SurfaceKind::Sphere: {
        const Vec3 n = normal(p);
        // e_u points east (increasing longitude), e_v north (increasing v = latitude).
        Vec3 east = Vec3::UnitZ().cross(n);
        if (east.norm() < 1e-12) east = Vec3::UnitY(); // at a pole any tangent will do
        east.normalize();
        const Vec3 north = n.cross(east);
        return {east, north, n};
    }
    case SurfaceKind::Mesh:
        return model_frame(*m_model, p);
    }
    return {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
}

Vec2 Surface::uv(const Vec3& p) const {
    switch (m_kind) {
    case SurfaceKind::Plane:
        return uv_of_domain(Vec2(p.x(), p.y()));
    case SurfaceKind::Cylinder: {
        const double phi = std::atan2(p.y(), p.x());
        return Vec2(wrap(phi / TWO_PI, 1.0), wrap(p.z() / m_period.y(), 1.0));
    }
    case SurfaceKind::Sphere: {
        const double r = p.norm();
        const double lon = std::atan2(p.y(), p.x());
        const double colat = std::acos(std::clamp(p.z() / r, -1.0, 1.0));
        return Vec2(wrap(lon / TWO_PI, 1.0), std::min(1.0 - colat / PI, std::nextafter(1.0, 0.0)));
    }
    case SurfaceKind::Mesh:
        return m_model->uv(m_model->closest(p));
    }
    return Vec2::Zero();
}

Vec3 Surface::project(const Vec3& p) const {
    switch (m_kind) {
    case SurfaceKind::Plane:
        return Vec3(p.x(), p.y(), 0.0);
    case SurfaceKind::Cylinder: {
        const Vec3 n = normal(p);
        return Vec3(m_radius * n.x(), m_radius * n.y(), p.z());
    }
    case SurfaceKind::Sphere:
        return m_radius * normal(p);
    case SurfaceKind::Mesh:
        return m_model->closest(p).point;
    }
    return p;
}

} // namespace crackle::mesh
