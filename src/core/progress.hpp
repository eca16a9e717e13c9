#pragma once
/// @file A progress bar on stderr for steps longer than about a second, only when stderr is
/// a terminal and output is not quieted (CI logs and pipes stay clean).

#include "core/timer.hpp"

#include <string>

namespace crackle {

/// Globally enables or disables progress bars (the CLI's --quiet turns them off).
void set_progress_enabled(bool enabled);

class Progress {
public:
    /// @param label  what is running ("repulsion")
    /// @param total  number of work units (iterations, events); 0 = unknown
    Progress(std::string label, double total);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Reports `done` of `total` units finished; cheap when nothing is drawn.
    void update(double done);
    void finish();

private:
    void draw(double done);
    std::string m_label;
    double m_total;
    Timer m_timer;
    double m_last_draw = -1.0;
    bool m_active;
    bool m_drawn = false;
};

} // namespace crackle
