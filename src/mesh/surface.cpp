#include "mesh/surface.hpp"

#include "core/error.hpp"

namespace crackle::mesh {

const char* to_string(SurfaceKind kind) {
    switch (kind) {
    case SurfaceKind::Plane:
        return "plane";
    case SurfaceKind::Cylinder:
        return "cylinder";
    case SurfaceKind::Sphere:
        return "sphere";
    }
    return "?";
}

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
    }
}

double Surface::area() const {
    if (m_kind == SurfaceKind::Sphere) return 4.0 * PI * sqr(m_radius);
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
    }
    return p;
}

} // namespace crackle::mesh
