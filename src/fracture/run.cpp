#include "fracture/run.hpp"

#include "core/log.hpp"

namespace crackle::fracture {

bool EventLog::full(double time) {
    if (m_events.size() < m_options.max_events) return false;
    m_capped = true;
    log::warn("fracture stopped at simulation.max_events = ", m_options.max_events, " (t = ", time, " of ",
              m_options.duration, ")");
    return true;
}

} // namespace crackle::fracture
