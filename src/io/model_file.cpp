// The artist's model through assimp (issue 30): nodes walked with their transforms, the unit
// applied, seams welded for the simulation, the UV layout kept per corner, and the checks a
// layer needs before anything is grown on it.
#include "io/model_file.hpp"

#include "core/error.hpp"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numeric>
#include <unordered_map>

namespace crackle::io {

namespace {

/// The triangles as the file has them, in model units, transforms applied.
struct Soup {
    std::vector<Vec3> corners; ///< 3 per triangle
    std::vector<Vec2> uv;      ///< 3 per triangle, when every mesh has the UV set
    std::size_t file_vertices = 0, points = 0, lines = 0, triangles_without_uv = 0;
    std::vector<std::string> nodes;
    int uv_sets = 1000;
};

std::string short_text(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

Vec3 transformed(const aiMatrix4x4& m, const aiVector3D& p) {
    const aiVector3D q = m * p;
    return Vec3(q.x, q.y, q.z);
}

void take_mesh(const aiMesh& mesh, const aiMatrix4x4& transform, int uv_set, Soup& soup) {
    soup.file_vertices += mesh.mNumVertices;
    const bool has_uv = mesh.HasTextureCoords(static_cast<unsigned>(uv_set));
    int sets = 0;
    while (sets < AI_MAX_NUMBER_OF_TEXTURECOORDS && mesh.HasTextureCoords(static_cast<unsigned>(sets)))
        ++sets;
    soup.uv_sets = std::min(soup.uv_sets, sets);
    // A mirroring transform (negative determinant) turns the winding over: turn it back.
    const bool mirrored = transform.Determinant() < 0;
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices == 1) ++soup.points;
        if (face.mNumIndices == 2) ++soup.lines;
        if (face.mNumIndices != 3) continue;
        const std::array<unsigned, 3> idx =
            mirrored ? std::array<unsigned, 3>{face.mIndices[0], face.mIndices[2], face.mIndices[1]}
                     : std::array<unsigned, 3>{face.mIndices[0], face.mIndices[1], face.mIndices[2]};
        for (unsigned i : idx) {
            soup.corners.push_back(transformed(transform, mesh.mVertices[i]));
            const aiVector3D t = has_uv ? mesh.mTextureCoords[uv_set][i] : aiVector3D(0, 0, 0);
            soup.uv.emplace_back(t.x, t.y);
        }
        if (!has_uv) ++soup.triangles_without_uv;
    }
}

/// Walks the node tree from the root with each node's transform; takes the meshes of every node
/// (no name) or of the named node and its children.
Soup collect(const aiScene& scene, const ModelOptions& options, const std::filesystem::path& file) {
    Soup soup;
    std::vector<std::string> named; // every node that has meshes, for the message
    bool found = options.node.empty();
    std::function<void(const aiNode&, const aiMatrix4x4&, bool)> walk = [&](const aiNode& node,
                                                                            const aiMatrix4x4& parent, bool taking) {
        const aiMatrix4x4 transform = parent * node.mTransformation;
        const std::string name = node.mName.C_Str();
        const bool picked = !options.node.empty() && name == options.node;
        found = found || picked;
        taking = taking || picked;
        if (node.mNumMeshes > 0) named.push_back(name);
        if (taking && node.mNumMeshes > 0) soup.nodes.push_back(name);
        for (unsigned m = 0; taking && m < node.mNumMeshes; ++m)
            take_mesh(*scene.mMeshes[node.mMeshes[m]], transform, options.uv_set, soup);
        for (unsigned c = 0; c < node.mNumChildren; ++c)
            walk(*node.mChildren[c], transform, taking);
    };
    walk(*scene.mRootNode, aiMatrix4x4(), options.node.empty());
    if (!found) {
        std::string list;
        for (const std::string& n : named)
            list += (list.empty() ? "" : ", ") + ("\"" + n + "\"");
        throw InputError(options.where + " " + file.string(), "no node named \"" + options.node + "\"",
                         "set surface.node to one of the nodes with meshes: " + (list.empty() ? "(none)" : list)
                             + ", or leave it out to merge them all");
    }
    return soup;
}

/// Metres per model unit: surface.scale when given, else what the file says.
std::pair<double, std::string> unit_scale(const aiScene& scene, const ModelOptions& options) {
    if (options.scale > 0) return {options.scale, "surface.scale"};
    if (scene.mMetaData) {
        // FBX: centimetres per unit (assimp leaves the coordinates in the file's units), stored as
        // a double or a float depending on the importer.
        double factor = 0;
        float as_float = 0;
        if (!scene.mMetaData->Get("UnitScaleFactor", factor) && scene.mMetaData->Get("UnitScaleFactor", as_float))
            factor = as_float;
        if (factor > 0 && std::isfinite(factor))
            return {factor / 100.0, "the file (UnitScaleFactor " + short_text(factor) + " cm per unit)"};
    }
    return {1.0, "none in the file: 1 m per unit (set surface.scale)"};
}

/// Merges corners closer than `tolerance` (seams split for UVs or normals): index per corner.
std::vector<int> weld(const std::vector<Vec3>& corners, double tolerance, std::vector<Vec3>& positions) {
    struct CellHash {
        std::size_t operator()(const std::array<long long, 3>& c) const {
            return static_cast<std::size_t>(c[0] * 73856093LL ^ c[1] * 19349663LL ^ c[2] * 83492791LL);
        }
    };
    std::unordered_map<std::array<long long, 3>, std::vector<int>, CellHash> cells;
    auto cell = [&](const Vec3& p) {
        return std::array<long long, 3>{std::llround(std::floor(p.x() / tolerance)),
                                        std::llround(std::floor(p.y() / tolerance)),
                                        std::llround(std::floor(p.z() / tolerance))};
    };
    std::vector<int> index(corners.size());
    for (std::size_t i = 0; i < corners.size(); ++i) {
        const Vec3& p = corners[i];
        const auto c = cell(p);
        int match = -1;
        for (long long dx = -1; dx <= 1 && match < 0; ++dx)
            for (long long dy = -1; dy <= 1 && match < 0; ++dy)
                for (long long dz = -1; dz <= 1 && match < 0; ++dz) {
                    const auto it = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
                    if (it == cells.end()) continue;
                    for (int v : it->second)
                        if ((positions[static_cast<std::size_t>(v)] - p).norm() <= tolerance) {
                            match = v;
                            break;
                        }
                }
        if (match < 0) {
            match = static_cast<int>(positions.size());
            positions.push_back(p);
            cells[c].push_back(match);
        }
        index[i] = match;
    }
    return index;
}

int find_root(std::vector<int>& parent, int x) {
    while (parent[static_cast<std::size_t>(x)] != x) {
        parent[static_cast<std::size_t>(x)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
        x = parent[static_cast<std::size_t>(x)];
    }
    return x;
}

/// Components, boundary edges and loops; refuses edges shared by more than two faces.
void check_topology(ModelMesh& m, const std::string& where) {
    std::map<std::pair<int, int>, int> edge_faces;
    for (const auto& t : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const int a = t[static_cast<std::size_t>(k)], b = t[static_cast<std::size_t>((k + 1) % 3)];
            ++edge_faces[{std::min(a, b), std::max(a, b)}];
        }
    std::size_t non_manifold = 0;
    Vec3 example = Vec3::Zero();
    std::vector<int> vertex_parent(m.positions.size()), boundary_parent(m.positions.size());
    std::iota(vertex_parent.begin(), vertex_parent.end(), 0);
    std::iota(boundary_parent.begin(), boundary_parent.end(), 0);
    std::vector<char> on_boundary(m.positions.size(), 0);
    for (const auto& [edge, faces] : edge_faces) {
        if (faces > 2 && non_manifold++ == 0) example = m.positions[static_cast<std::size_t>(edge.first)];
        if (faces == 1) {
            ++m.summary.boundary_edges;
            on_boundary[static_cast<std::size_t>(edge.first)] = on_boundary[static_cast<std::size_t>(edge.second)] = 1;
            boundary_parent[static_cast<std::size_t>(find_root(boundary_parent, edge.first))] =
                find_root(boundary_parent, edge.second);
        }
        vertex_parent[static_cast<std::size_t>(find_root(vertex_parent, edge.first))] =
            find_root(vertex_parent, edge.second);
    }
    if (non_manifold > 0)
        throw InputError(where,
                         std::to_string(non_manifold) + " edges are shared by more than two faces (the first near ("
                             + short_text(example.x()) + ", " + short_text(example.y()) + ", " + short_text(example.z())
                             + ") m): a layer cannot grow across them",
                         "make the surface manifold (Blender: Select > Select All by Trait > Non Manifold, then "
                         "separate or delete those faces)");
    std::vector<char> seen(m.positions.size(), 0), seen_loop(m.positions.size(), 0);
    for (const auto& t : m.triangles) {
        const int r = find_root(vertex_parent, t[0]);
        if (!seen[static_cast<std::size_t>(r)]) ++m.summary.components;
        seen[static_cast<std::size_t>(r)] = 1;
    }
    for (std::size_t v = 0; v < m.positions.size(); ++v)
        if (on_boundary[v]) {
            const int r = find_root(boundary_parent, static_cast<int>(v));
            if (!seen_loop[static_cast<std::size_t>(r)]) ++m.summary.boundary_loops;
            seen_loop[static_cast<std::size_t>(r)] = 1;
        }
}

/// Welds the soup, drops nothing: refuses non-finite coordinates and degenerate faces.
ModelMesh build(const Soup& soup, double scale, const std::string& where) {
    ModelMesh m;
    std::vector<Vec3> corners = soup.corners;
    std::size_t non_finite = 0;
    Vec3 lo = Vec3::Constant(INFINITY), hi = Vec3::Constant(-INFINITY);
    for (Vec3& p : corners) {
        p *= scale;
        if (!p.allFinite()) {
            ++non_finite;
            continue;
        }
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
    }
    if (non_finite > 0)
        throw InputError(where, std::to_string(non_finite) + " triangle corners have coordinates that are not numbers",
                         "re-export the model (NaN or infinite positions)");
    const double diagonal = (hi - lo).norm();
    const std::vector<int> index = weld(corners, std::max(diagonal, 1e-9) * 1e-7, m.positions);
    std::size_t degenerate = 0;
    Vec3 example = Vec3::Zero();
    const double min_area = 1e-14 * diagonal * diagonal;
    for (std::size_t t = 0; t * 3 < index.size(); ++t) {
        const std::array<int, 3> tri = {index[3 * t], index[3 * t + 1], index[3 * t + 2]};
        const Vec3& a = m.positions[static_cast<std::size_t>(tri[0])];
        const double area = 0.5
                            * (m.positions[static_cast<std::size_t>(tri[1])] - a)
                                  .cross(m.positions[static_cast<std::size_t>(tri[2])] - a)
                                  .norm();
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) {
            // Collapsed: two corners at one point (a pole's fan, a welded sliver). It has no
            // surface and its neighbours close over it: dropped, counted.
            ++m.summary.collapsed_faces;
            continue;
        }
        if (area <= min_area) {
            if (degenerate++ == 0) example = a;
            continue;
        }
        m.triangles.push_back(tri);
        m.summary.area += area;
    }
    if (degenerate > 0)
        throw InputError(where,
                         std::to_string(degenerate) + " of " + std::to_string(index.size() / 3)
                             + " faces have no area (the first near (" + short_text(example.x()) + ", "
                             + short_text(example.y()) + ", " + short_text(example.z()) + ") m)",
                         "remove them (Blender: Mesh > Clean Up > Degenerate Dissolve) and export again");
    m.summary.box_min = lo;
    m.summary.box_max = hi;
    return m;
}

} // namespace

ModelMesh read_model(const std::filesystem::path& file, const ModelOptions& options) {
    const std::string where = options.where + " " + file.string();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
        throw InputError(where, "no such file", "give the path of a model file (relative to the preset's folder)");
    Assimp::Importer importer;
    // Polygons become triangles; points and lines are sorted into meshes of their own (counted).
    const aiScene* scene = importer.ReadFile(file.string(), aiProcess_Triangulate | aiProcess_SortByPType);
    if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
        throw InputError(where, std::string("assimp could not read it: ") + importer.GetErrorString(),
                         "give a glTF/GLB, OBJ, FBX, COLLADA, PLY, 3DS or STL file (any format assimp reads)");
    const Soup soup = collect(*scene, options, file);
    if (soup.corners.empty())
        throw InputError(where,
                         "no triangles to grow a layer on (" + std::to_string(soup.points) + " points, "
                             + std::to_string(soup.lines) + " lines"
                             + (options.node.empty() ? "" : " under node \"" + options.node + "\"") + ")",
                         "give a model with faces");
    const int sets = soup.uv_sets == 1000 ? 0 : soup.uv_sets;
    if (options.uv_set > 0 && options.uv_set >= sets)
        throw InputError(where,
                         "no UV set " + std::to_string(options.uv_set) + " (every mesh taken has "
                             + std::to_string(sets) + ")",
                         "set surface.uv_set between 0 and " + std::to_string(std::max(sets - 1, 0)));
    const auto [scale, scale_source] = unit_scale(*scene, options);
    ModelMesh m = build(soup, scale, where);
    check_topology(m, where);
    ModelSummary& s = m.summary;
    s.file_vertices = soup.file_vertices;
    s.scale = scale;
    s.scale_source = scale_source;
    s.nodes = soup.nodes;
    s.uv_sets = sets;
    if (sets > options.uv_set) {
        // Corners of the kept triangles, in order (build() refused any it would have dropped).
        m.corner_uv.resize(m.triangles.size());
        for (std::size_t t = 0; t < m.triangles.size(); ++t)
            for (std::size_t k = 0; k < 3; ++k) {
                const Vec2& uv = soup.uv[3 * t + k];
                m.corner_uv[t][k] = uv;
                s.uv_corners_outside += uv.x() < 0 || uv.x() > 1 || uv.y() < 0 || uv.y() > 1;
            }
    }
    return m;
}

} // namespace crackle::io
