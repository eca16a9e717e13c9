#pragma once
/// @file `crackle bake --watch PRESET.toml`: re-bakes the preview whenever the preset file is
/// saved, for an artist tweaking a preset in an editor beside the viewer.

#include "app/commands/bake.hpp"

#include <atomic>
#include <functional>
#include <ostream>

namespace crackle::app {

/// How a watch is driven: the CLI stops it on Ctrl-C; tests stop it themselves and hear of
/// every bake.
struct WatchControl {
    std::atomic<bool>* stop = nullptr; ///< set to end the watch (checked between polls)
    double poll_seconds = 0.2;         ///< how often the file is read
    /// Called after every bake: its number (from 1) and whether it succeeded.
    std::function<void(int, bool)> on_bake;
};

/// Bakes the preview of `args.preset` (a file), then again each time the file's content
/// changes, until `control.stop` is set (Ctrl-C from the CLI: `install_interrupt_stop`). A bad
/// preset or a numeric failure prints its error to `err` and the watch goes on. Returns 0 when
/// stopped; throws InputError (exit 2) when the preset is not a file it can watch.
int watch_command(const BakeArgs& args, const GlobalOptions& global, std::ostream& out, std::ostream& err,
                  const WatchControl& control);

/// Makes the first Ctrl-C (SIGINT) set `stop`; a second one ends the process as usual.
void install_interrupt_stop(std::atomic<bool>& stop);

} // namespace crackle::app
