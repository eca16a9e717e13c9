#pragma once
/// @file The crack network as curves for baking (issue 35): where the simulation says the cracks
/// are, as chains between junctions and tips (running straight on through a junction where two
/// links continue each other, so a T's bar is one chain), in texture space and in the final
/// (deformed) configuration, the centreline between a crack's two lips. The bake smooths these
/// chains into curves and shapes the grooves from the distance to them, so the relief does not
/// show the element-scale polyline (render/crack_curves.hpp).

#include "fracture/crack_pattern.hpp"
#include "post/crack_times.hpp"

#include <vector>

namespace crackle::post {

/// One chain of the crack network: a polyline from a tip or a junction it ends on to the next (or
/// a closed loop), through nodes of degree 2 and the junctions it runs straight through.
struct CrackChain {
    /// Texture coordinates, unwrapped along the chain (consecutive points are the nearest
    /// periodic images of each other, so a chain may leave [0, 1)).
    std::vector<Vec2> uv;
    /// per point: the gap between the crack's lips at the top in the final configuration (m):
    /// the simulated opening plus what the post-processing's shrinkage pulled the pieces apart;
    /// 0 at a tip that did not open
    std::vector<float> opening;
    std::vector<float> time; ///< per point: when the crack formed, 0 = first crack, 1 = last
    bool tip_front = false;  ///< the first point is a crack tip (a node of degree 1)
    bool tip_back = false;   ///< the last point is a crack tip
    bool closed = false;     ///< a loop through nodes of degree 2 only (first point repeated at the end)
};

/// The crack network of `pattern`: split, spring and graph cracks linked along their edges
/// (the copies a split made of one reference point are one node, at the centre of the smallest
/// circle round them: where the pieces meeting there are equally far; a hanging node's far side
/// is the coarse lip across the gap),
/// removed elements linked across shared edges (the chain runs through their centroids).
/// `copies` holds, for every pattern vertex, the final texture coordinates of each piece's copy
/// of it (canonical); `metric` its metres per unit of u and v. A link's gap (its opening) is
/// the mean separation of its two lips' end points.
std::vector<CrackChain> crack_chains(const fracture::CrackPattern& pattern,
                                     const std::vector<std::vector<Vec2>>& copies, const std::vector<Vec2>& metric,
                                     const CrackTimes& times);

} // namespace crackle::post
