#pragma once
/// @file The artist's own model (issue 30): any triangle mesh assimp reads (glTF/GLB, OBJ, FBX,
/// COLLADA, PLY, 3DS, STL, ...), with its node transforms applied, in metres, one node picked or
/// all merged. Two views of the same triangles: the simulation's, welded (duplicate vertices along
/// UV and normal seams merged, so a cylinder's seam is no border), and the bake's UV layout, kept
/// per triangle corner. Whatever the simulation cannot grow a layer on is refused here with exit 2
/// and what to do: no triangles (points or lines only), coordinates that are not numbers,
/// degenerate faces, edges shared by more than two faces.

#include "core/math.hpp"
#include "mesh/model_surface.hpp"

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace crackle::io {

struct ModelOptions {
    /// surface.node: the node whose meshes to take ("" = every mesh of the scene, merged).
    std::string node;
    /// surface.uv_set: which texture-coordinate channel is the bake's layout.
    int uv_set = 0;
    /// surface.scale: metres per model unit; 0 = from the file (FBX's UnitScaleFactor; COLLADA's
    /// <unit> is applied by its node transforms; glTF is metres), else 1.
    double scale = 0;
    std::string where = "surface.file"; ///< what messages name
};

/// What the model is, for the report and the checks of later stages.
struct ModelSummary {
    std::size_t file_vertices = 0; ///< vertices as the file has them (seams split)
    std::size_t components = 0;    ///< connected pieces of surface
    std::size_t boundary_edges = 0;
    std::size_t boundary_loops = 0; ///< 0 for closed surfaces
    double area = 0;                ///< m²
    Vec3 box_min = Vec3::Zero(), box_max = Vec3::Zero();
    double scale = 1;               ///< metres per model unit used
    std::string scale_source;       ///< "surface.scale", "file (FBX UnitScaleFactor 2.54 cm)", "none in the file: 1"
    std::vector<std::string> nodes; ///< the nodes whose meshes were taken, in scene order
    int uv_sets = 0;                ///< texture-coordinate channels every mesh has
    std::size_t uv_corners_outside = 0; ///< corners whose UV lies outside [0, 1]² (tiling, UDIMs)
    /// Faces dropped because two of their corners are one point once welded (a pole's fan of
    /// slivers, a collapsed edge): they carry no surface.
    std::size_t collapsed_faces = 0;
};

/// The model: welded vertices (metres, node transforms applied) and the triangles over them,
/// wound as in the file (counter-clockwise seen from outside for the usual exporters), and per
/// triangle corner the UV layout of options.uv_set (v up: assimp's convention, the one the bake's
/// maps are read with); no UVs when the file has none.
struct ModelMesh : mesh::TriangleModel {
    ModelSummary summary;
};

/// Reads and checks a model. Throws InputError (exit 2) naming options.where, the file and the
/// problem: unreadable or unsupported (assimp's own message included), no triangles, no node of
/// that name (the names listed), a missing UV set, non-finite coordinates, degenerate faces,
/// non-manifold edges.
ModelMesh read_model(const std::filesystem::path& file, const ModelOptions& options = {});

} // namespace crackle::io
