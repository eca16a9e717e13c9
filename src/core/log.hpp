#pragma once
/// @file Logging through one sink (ipc-toolkit: logger.hpp). Library code never prints
/// directly; the CLI sets the verbosity from -v/-q and the stream (stderr by default).

#include <ostream>
#include <sstream>
#include <string>

namespace crackle::log {

enum class Level { Error = 0, Warn = 1, Info = 2, Debug = 3 };

void set_level(Level level);
Level level();
/// Redirects log output (tests capture it); nullptr restores std::cerr.
void set_stream(std::ostream* os);

void write(Level level, const std::string& message);

template <typename... Args> void emit(Level lvl, const Args&... args) {
    if (static_cast<int>(lvl) > static_cast<int>(level())) return;
    std::ostringstream os;
    (os << ... << args);
    write(lvl, os.str());
}

template <typename... Args> void error(const Args&... args) {
    emit(Level::Error, args...);
}
template <typename... Args> void warn(const Args&... args) {
    emit(Level::Warn, args...);
}
template <typename... Args> void info(const Args&... args) {
    emit(Level::Info, args...);
}
template <typename... Args> void debug(const Args&... args) {
    emit(Level::Debug, args...);
}

} // namespace crackle::log
