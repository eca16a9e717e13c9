#pragma once
/// @file `crackle presets list | show | doc`: the built-in presets, one resolved, the reference.

#include "io/preset.hpp"

#include <ostream>

namespace crackle::app {

/// `presets list`: every built-in preset with its one-line summary.
int presets_list(std::ostream& out);
/// `presets show`: the resolved preset as TOML, every key with its source.
int presets_show(const io::PresetRequest& request, std::ostream& out);
/// `presets doc`: the Markdown reference of every key (docs/presets.md).
int presets_doc(std::ostream& out);

} // namespace crackle::app
