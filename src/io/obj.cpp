#include "io/obj.hpp"

#include <cstdio>
#include <map>
#include <tuple>

namespace crackle::io {

std::string surface_mesh_obj(const mesh::SurfaceMesh& m, const mesh::Surface& surface) {
    using mesh::face_id;
    std::string out = "# crackle surface mesh: " + std::to_string(m.num_vertices()) + " vertices, "
                      + std::to_string(m.num_faces()) + " faces\n";
    // One OBJ vertex per (vertex, periodic offset) pair in use.
    std::map<std::tuple<std::size_t, int, int>, std::size_t> index;
    std::vector<std::array<std::size_t, 3>> faces(m.num_faces());
    char buf[160];
    for (std::size_t fi = 0; fi < m.num_faces(); ++fi) {
        const auto f = face_id(fi);
        for (int k = 0; k < 3; ++k) {
            const auto& face = m.faces[f];
            const auto kk = static_cast<std::size_t>(k);
            const auto key = std::make_tuple(mesh::ix(face.v[kk]), face.offset[kk].x(), face.offset[kk].y());
            auto it = index.find(key);
            if (it == index.end()) {
                const Vec3 p = m.corner_position(f, k);
                Vec2 uv;
                if (surface.periodic()) {
                    const Vec2 d = m.corner_domain(f, k);
                    uv = Vec2(d.x() / surface.period().x(), d.y() / surface.period().y());
                } else {
                    uv = surface.uv(p);
                }
                const Vec3 n = surface.normal(m.positions[face.v[kk]]);
                std::snprintf(buf, sizeof buf, "v %.9g %.9g %.9g\nvt %.9g %.9g\nvn %.6g %.6g %.6g\n", p.x(), p.y(),
                              p.z(), uv.x(), uv.y(), n.x(), n.y(), n.z());
                out += buf;
                it = index.emplace(key, index.size() + 1).first;
            }
            faces[fi][kk] = it->second;
        }
    }
    for (const auto& f : faces) {
        std::snprintf(buf, sizeof buf, "f %zu/%zu/%zu %zu/%zu/%zu %zu/%zu/%zu\n", f[0], f[0], f[0], f[1], f[1], f[1],
                      f[2], f[2], f[2]);
        out += buf;
    }
    return out;
}

} // namespace crackle::io
