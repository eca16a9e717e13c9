#pragma once
/// @file When each crack formed. The methods record fracture events (time and reference position,
/// thesis §5.10's temporal sequences, Fig. 5.30); a crack edge or removed element takes the time of
/// the nearest event. Baking uses it so the first (primary) cracks are wide and deep and the
/// last ones fine, as in drying mud, where early cracks keep opening while later ones stay
/// hairlines.

#include "fracture/crack_pattern.hpp"

#include <vector>

namespace crackle::post {

struct CrackTimes {
    std::vector<double> edge;    ///< per pattern.cracks entry: formation time, 0 = first crack, 1 = last
    std::vector<double> removed; ///< per pattern face: the same for removed faces (0 elsewhere)
};

/// Normalised formation times; all 0 when the pattern has fewer than two fracture events.
CrackTimes crack_times(const fracture::CrackPattern& pattern);

} // namespace crackle::post
