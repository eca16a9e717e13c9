#include "app/commands/presets.hpp"

#include "io/preset_schema.hpp"

#include <iomanip>

namespace crackle::app {

int presets_list(std::ostream& out) {
    for (const std::string& name : io::builtin_preset_names())
        out << std::left << std::setw(24) << name << io::builtin_preset_summary(name) << "\n";
    return 0;
}

int presets_show(const io::PresetRequest& request, std::ostream& out) {
    out << io::load_preset(request).to_toml();
    return 0;
}

int presets_doc(std::ostream& out) {
    out << io::schema_markdown();
    return 0;
}

} // namespace crackle::app
