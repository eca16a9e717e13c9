#include "core/timer.hpp"

#include <fstream>
#include <sstream>

namespace crackle {

double peak_memory_mb() {
    std::ifstream status("/proc/self/status");
    std::string line;
    while (std::getline(status, line)) {
        if (line.rfind("VmHWM:", 0) == 0) {
            std::istringstream is(line.substr(6));
            double kib = 0;
            is >> kib;
            return kib / 1024.0;
        }
    }
    return 0.0;
}

} // namespace crackle
