#pragma once
/// @file Options every command shares (cli/cli.cpp fills them).

namespace crackle::app {

/// Options every command shares.
struct GlobalOptions {
    bool quiet = false;
};

} // namespace crackle::app
