#pragma once
/// @file The artist's model as a surface to grow a layer on (issue 30): its triangles (welded,
/// in metres) with the UV layout per corner, and the queries the simulation asks of a surface
/// that has no formula: the closest point, the smooth normal there, the UV there.

#include "core/math.hpp"

#include <array>
#include <memory>
#include <vector>

namespace crackle::mesh {

/// A triangle model as read from a file (io::read_model): welded vertices, triangles over them,
/// and the bake's UV layout per triangle corner (empty when the file has none).
struct TriangleModel {
    std::vector<Vec3> positions;
    std::vector<std::array<int, 3>> triangles;
    std::vector<std::array<Vec2, 3>> corner_uv;
};

class ModelSurface {
public:
    explicit ModelSurface(TriangleModel model);
    ~ModelSurface();
    ModelSurface(const ModelSurface&) = delete;
    ModelSurface& operator=(const ModelSurface&) = delete;

    /// The closest point of the model to a point: its triangle and barycentric coordinates.
    struct Hit {
        int triangle = -1;
        Vec3 point = Vec3::Zero();
        Vec3 barycentric = Vec3::Zero();
        double distance = 0;
    };
    Hit closest(const Vec3& p) const;
    /// The smooth unit normal at a hit: the area-weighted vertex normals, interpolated.
    Vec3 normal(const Hit& hit) const;
    /// The UV layout at a hit, in its own triangle's corners (a seam's two sides differ).
    Vec2 uv(const Hit& hit) const;

    const TriangleModel& model() const { return m_model; }
    double area() const { return m_area; }
    bool has_uv() const { return !m_model.corner_uv.empty(); }

private:
    TriangleModel m_model;
    std::vector<Vec3> m_vertex_normals;
    double m_area = 0;
    struct Tree;
    std::unique_ptr<Tree> m_tree;
};

} // namespace crackle::mesh
