// graph-fem's edge damage on the wedge layer (graph-fem digest §1.4–1.7, errata E1/E2, §7.8 tests 3–5, 8),
// on the plane, the cylinder and the sphere.
#include "core/rng.hpp"
#include "sim/wedge_element.hpp"
#include "support/fem_fixture.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <doctest/doctest.h>

#include <algorithm>

using namespace crackle;
using namespace crackle::sim;
using mesh::SurfaceKind;
using test::Layer;
using test::LayerSpec;

namespace {

LayerSpec layer_on(SurfaceKind kind, std::size_t elements = 300) {
    LayerSpec s;
    s.kind = kind;
    s.size = kind == SurfaceKind::Sphere ? Vec2(0.1, 0.1) : Vec2(0.2, 0.2);
    s.elements = elements;
    s.fem.tolerance = 1e-12;
    return s;
}

constexpr std::array<SurfaceKind, 3> SURFACES = {SurfaceKind::Plane, SurfaceKind::Cylinder, SurfaceKind::Sphere};

/// T (in-plane edge strains from (εxx, εyy, γxy) in the element's frame e₁ = edge 0) and the
/// frame, rebuilt here from the element's corners, independently of wedge_element.cpp.
struct Frame {
    Mat3 R, T;
};
Frame frame_of(const wedge::Nodes& n) {
    const wedge::EdgeFrame f = wedge::edge_frame(n);
    Frame out;
    out.R.col(0) = f.edge[0];
    out.R.col(1) = f.normal.cross(f.edge[0]);
    out.R.col(2) = f.normal;
    for (int k = 0; k < 3; ++k) {
        const Vec3& d = f.edge[static_cast<std::size_t>(k)];
        const double c = d.dot(out.R.col(0)), s = d.dot(out.R.col(1));
        out.T.row(k) << c * c, s * s, c * s;
    }
    return out;
}

/// Nodal displacements of the uniform strain whose only in-plane edge strain is edge k's
/// (ε_k = 1e-3, the other two 0, no out-of-plane strain): the opening mode of a broken edge.
wedge::Vec18 edge_stretch_mode(const wedge::Nodes& n, int k) {
    const Frame f = frame_of(n);
    const Vec3 e = f.T.inverse() * (1e-3 * Vec3::Unit(k)); // (εxx, εyy, γxy) local
    Mat3 local = Mat3::Zero();
    local(0, 0) = e[0];
    local(1, 1) = e[1];
    local(0, 1) = local(1, 0) = 0.5 * e[2];
    const Mat3 strain = f.R * local * f.R.transpose(); // global, symmetric: u = strain · x
    wedge::Vec18 q;
    for (std::size_t i = 0; i < 6; ++i)
        q.segment<3>(static_cast<Eigen::Index>(3 * i)) = strain * n[i];
    return q;
}

Eigen::MatrixXd dense(const Eigen::SparseMatrix<double, Eigen::RowMajor>& K) {
    return Eigen::MatrixXd(K);
}

} // namespace

TEST_SUITE("sim") {
    TEST_CASE("edge damage: with no broken edge an element's material and stiffness are the wedge FEM's") {
        for (SurfaceKind kind : SURFACES) {
            CAPTURE(mesh::to_string(kind));
            Layer layer(layer_on(kind));
            const FemModel& m = *layer.model;
            for (std::size_t f = 0; f < m.mesh().num_faces(); f += 7) {
                const auto id = mesh::face_id(f);
                CHECK(m.broken_edges(id) == 0u);
                const wedge::Mat6 D = wedge::elasticity(m.material(id).young_modulus, m.poisson_ratio());
                CHECK((m.element_elasticity(id) - D).norm() == 0.0);
                const wedge::Nodes ref = m.reference_nodes(id);
                CHECK((wedge::edge_projector(ref, 0) - wedge::Mat6::Identity()).norm() == 0.0);
                CHECK((wedge::stiffness(ref, m.element_elasticity(id))
                       - wedge::stiffness(ref, m.material(id).young_modulus, m.poisson_ratio()))
                          .norm()
                      == 0.0);
                // Rotating strains into the frame and back is the identity.
                const Frame fr = frame_of(ref);
                const wedge::Mat6 Q = wedge::strain_rotation(fr.R);
                CHECK((Q * wedge::strain_rotation(fr.R.transpose()) - wedge::Mat6::Identity()).norm() < 1e-12);
            }
        }
    }

    TEST_CASE("edge damage: Π is a projector, a broken edge carries no tension at any Gauss point and its stretch "
              "costs no energy (E1: the mask is 1 − ζ)") {
        Rng rng(7, 0);
        for (SurfaceKind kind : SURFACES) {
            CAPTURE(mesh::to_string(kind));
            Layer layer(layer_on(kind));
            const FemModel& m = *layer.model;
            for (std::size_t f = 0; f < m.mesh().num_faces(); f += 11) {
                const wedge::Nodes ref = m.reference_nodes(mesh::face_id(f));
                const wedge::Mat6 D = wedge::elasticity(1e9, 0.3);
                const wedge::Mat18 K0 = wedge::stiffness(ref, D);
                wedge::Vec18 q;
                for (int i = 0; i < 18; ++i)
                    q[i] = 1e-4 * rng.normal();
                for (unsigned mask = 1; mask < 8; ++mask) {
                    CAPTURE(f);
                    CAPTURE(mask);
                    const wedge::Mat6 P = wedge::edge_projector(ref, mask);
                    CHECK((P * P - P).norm() < 1e-10 * P.norm());
                    const wedge::Mat6 Dd = wedge::damaged_elasticity(D, P);
                    CHECK((Dd - Dd.transpose()).norm() < 1e-12 * D.norm());
                    for (const auto& g : wedge::quadrature()) {
                        const wedge::Vec6 s = Dd * (wedge::strain_matrix(ref, g.xi, g.eta, g.zeta) * q);
                        const Vec3 t = wedge::edge_tensions(ref, s);
                        const wedge::Vec6 s0 = D * (wedge::strain_matrix(ref, g.xi, g.eta, g.zeta) * q);
                        const double scale = wedge::edge_tensions(ref, s0).cwiseAbs().maxCoeff();
                        for (int k = 0; k < 3; ++k)
                            if ((mask >> k) & 1u) CHECK(std::abs(t[k]) < 1e-9 * scale);
                    }
                    const wedge::Mat18 K = wedge::stiffness(ref, Dd);
                    CHECK((K - K.transpose()).norm() < 1e-12 * K0.norm());
                    for (int k = 0; k < 3; ++k) {
                        const wedge::Vec18 mode = edge_stretch_mode(ref, k);
                        const double intact = mode.dot(K0 * mode);
                        CHECK(intact > 0);
                        if ((mask >> k) & 1u)
                            CHECK(std::abs(mode.dot(K * mode)) < 1e-10 * intact);
                        else
                            CHECK(mode.dot(K * mode) > 1e-3 * intact);
                    }
                    // Positive semi-definite with the rigid modes (and nothing else freed out of
                    // plane): the bottom nodes held, K_tt is positive definite.
                    const Eigen::SelfAdjointEigenSolver<wedge::Mat18> eig(K);
                    CHECK(eig.eigenvalues().minCoeff() > -1e-9 * eig.eigenvalues().maxCoeff());
                    const Eigen::Matrix<double, 9, 9> Ktt = K.bottomRightCorner<9, 9>();
                    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> top(Ktt);
                    CHECK(top.eigenvalues().minCoeff() > 0);
                }
            }
        }
    }

    TEST_CASE("edge damage: after many breaks K keeps its unknowns and nonzeros, matches a fresh assembly, and "
              "stays symmetric positive definite") {
        for (SurfaceKind kind : SURFACES) {
            CAPTURE(mesh::to_string(kind));
            LayerSpec spec = layer_on(kind, 200);
            spec.shrinkage = {0.01, 0.005};
            Layer layer(spec);
            FemModel& m = *layer.model;
            const auto rows = m.stiffness().rows();
            const auto nnz = m.stiffness().nonZeros();
            Rng rng(3, 0);
            // Every edge of the first ten faces (fully broken elements), then random ones.
            std::vector<std::pair<mesh::FaceId, int>> sides;
            for (std::size_t f = 0; f < 10; ++f)
                for (int k = 0; k < 3; ++k)
                    sides.emplace_back(mesh::face_id(f), k);
            for (int i = 0; i < 150; ++i)
                sides.emplace_back(mesh::face_id(rng.uniform_int(static_cast<std::uint32_t>(m.mesh().num_faces()))),
                                   static_cast<int>(rng.uniform_int(3)));
            for (std::size_t i = 0; i < sides.size(); i += 10)
                m.break_edges(std::vector<std::pair<mesh::FaceId, int>>(
                    sides.begin() + static_cast<std::ptrdiff_t>(i),
                    sides.begin() + static_cast<std::ptrdiff_t>(std::min(i + 10, sides.size()))));
            // Both sides of every broken edge carry the bit.
            for (const auto& [f, k] : sides) {
                const mesh::FaceNeighbor nb = m.mesh().neighbor(f, k);
                CHECK(((m.broken_edges(f) >> k) & 1u) == 1u);
                CHECK(((m.broken_edges(nb.face) >> nb.edge) & 1u) == 1u);
            }
            CHECK(m.stiffness().rows() == rows);
            CHECK(m.stiffness().nonZeros() == nnz);
            const Eigen::MatrixXd K = dense(m.stiffness());
            const Eigen::MatrixXd K2 = dense(m.assemble_from_scratch());
            CHECK((K - K2).norm() < 1e-12 * K2.norm());
            CHECK((K - K.transpose()).norm() < 1e-12 * K.norm());
            const Eigen::LLT<Eigen::MatrixXd> llt(K);
            CHECK(llt.info() == Eigen::Success);
            m.set_time(0.5);
            m.relax();
            for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v)
                CHECK(m.top_position(mesh::vertex_id(v)).allFinite());
        }
    }

    TEST_CASE("edge damage: a rolled-back break restores K, the masks and the positions exactly") {
        for (SurfaceKind kind : SURFACES) {
            CAPTURE(mesh::to_string(kind));
            LayerSpec spec = layer_on(kind, 200);
            spec.shrinkage = {0.01, 0.01};
            Layer layer(spec);
            FemModel& m = *layer.model;
            m.set_time(0.5);
            m.relax();
            const Eigen::MatrixXd K = dense(m.stiffness());
            const Vec3 x = m.top_position(mesh::vertex_id(5));
            m.begin_trial();
            m.break_edges({{mesh::face_id(4), 1}, {mesh::face_id(17), 0}});
            const SolveStats moved = m.relax();
            CHECK(m.broken_edges(mesh::face_id(4)) != 0u);
            CHECK(moved.energy_release > 0); // the break changed the equilibrium
            CHECK((dense(m.stiffness()) - K).norm() > 0);
            m.rollback();
            CHECK(m.broken_edges(mesh::face_id(4)) == 0u);
            CHECK(m.broken_edges(mesh::face_id(17)) == 0u);
            CHECK((dense(m.stiffness()) - K).norm() == 0.0);
            CHECK((m.top_position(mesh::vertex_id(5)) - x).norm() == 0.0);
        }
    }

    TEST_CASE("edge damage: a fully broken layer sheds its in-plane stress and keeps only its bonding") {
        // Isotropic shrinkage loads every edge; with every edge broken no element can carry
        // in-plane tension, on any surface (the "stress-free free layer" of the issue).
        for (SurfaceKind kind : SURFACES) {
            CAPTURE(mesh::to_string(kind));
            LayerSpec spec = layer_on(kind, 200);
            spec.shrinkage = {0.01, 0.01};
            spec.fem.stiffness_refresh = 0.0;
            Layer layer(spec);
            FemModel& m = *layer.model;
            std::vector<std::pair<mesh::FaceId, int>> all;
            for (std::size_t f = 0; f < m.mesh().num_faces(); ++f)
                for (int k = 0; k < 3; ++k)
                    all.emplace_back(mesh::face_id(f), k);
            m.set_time(0.5);
            m.relax();
            double before = 0;
            for (std::size_t f = 0; f < m.mesh().num_faces(); ++f)
                for (const auto& s : m.top_stress(mesh::face_id(f)))
                    before = std::max(before, wedge::edge_tensions(m.reference_nodes(mesh::face_id(f)), s).maxCoeff());
            m.break_edges(all);
            m.relax();
            double after = 0;
            for (std::size_t f = 0; f < m.mesh().num_faces(); ++f)
                for (const auto& s : m.top_stress(mesh::face_id(f)))
                    after = std::max(
                        after, wedge::edge_tensions(m.reference_nodes(mesh::face_id(f)), s).cwiseAbs().maxCoeff());
            CHECK(before > 1e-3 * spec.young * 0.005);
            CHECK(after < 1e-9 * before);
        }
    }
}
