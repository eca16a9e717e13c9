#include "app/run/naming.hpp"

#include "core/error.hpp"

#include <cstring>

namespace crackle::app {

namespace {

constexpr std::size_t MAX_COMPONENT = 200; // file systems allow 255 bytes; leave room for suffixes

/// Removes "{map}" with one separator beside it.
std::string without_map(std::string pattern) {
    for (const char* form : {"_{map}", "-{map}", ".{map}", "/{map}", "{map}_", "{map}-", "{map}.", "{map}/", "{map}"})
        if (const auto at = pattern.find(form); at != std::string::npos) return pattern.erase(at, std::strlen(form));
    return pattern;
}

} // namespace

std::string preset_file_name(const std::string& preset_name) {
    std::string name = preset_name;
    if (name.size() > 5 && name.substr(name.size() - 5) == ".toml") name = std::filesystem::path(name).stem().string();
    for (char& c : name)
        if (c == '/' || c == '\\') c = '-';
    return name;
}

OutputNames::OutputNames(std::string pattern, NameFields fields, std::string where)
    : m_pattern(std::move(pattern)), m_fields(std::move(fields)), m_where(std::move(where)) {
    const std::string fix = "use letters, digits, '-', '_', '.', '/' for subfolders and the fields {preset}, {seed}, "
                            "{variant}, {map}";
    // Unknown fields first: "{sede}" is a typo, not a name.
    for (std::size_t open = m_pattern.find('{'); open != std::string::npos; open = m_pattern.find('{', open + 1)) {
        const auto close = m_pattern.find('}', open);
        const std::string field = m_pattern.substr(open, close == std::string::npos ? 1 : close - open + 1);
        if (field != "{preset}" && field != "{seed}" && field != "{variant}" && field != "{map}")
            throw InputError(m_where, "unknown field '" + field + "' in the name '" + m_pattern + "'", fix);
    }
    for (const std::string& name : {expand("Color"), base()}) {
        if (name.empty()) throw InputError(m_where, "the output name is empty", fix);
        for (const char c : name)
            if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f || c == '\\' || c == ':')
                throw InputError(m_where,
                                 "the output name holds a character file names cannot (a control "
                                 "character, NUL, '\\\\' or ':')",
                                 fix);
        const std::filesystem::path p(name);
        if (p.is_absolute() || name.front() == '/')
            throw InputError(m_where, "the output name '" + name + "' is an absolute path",
                             "name files inside --out; " + fix);
        for (const auto& part : p) {
            if (part == ".." || part == ".")
                throw InputError(m_where, "the output name '" + name + "' would leave the output folder", fix);
            if (part.string().size() > MAX_COMPONENT)
                throw InputError(m_where,
                                 "a part of the output name is " + std::to_string(part.string().size()) + " bytes long",
                                 "keep each part under " + std::to_string(MAX_COMPONENT) + " bytes");
        }
    }
}

std::string OutputNames::expand(const std::string& map) const {
    std::string pattern =
        m_pattern.find("{map}") == std::string::npos && !map.empty() ? m_pattern + "_{map}" : m_pattern;
    if (map.empty()) pattern = without_map(pattern);
    std::string out;
    for (std::size_t i = 0; i < pattern.size();) {
        auto field = [&](const char* name, const std::string& value) {
            if (pattern.compare(i, std::strlen(name), name) != 0) return false;
            out += value;
            i += std::strlen(name);
            return true;
        };
        if (field("{preset}", m_fields.preset) || field("{seed}", std::to_string(m_fields.seed))
            || field("{variant}", m_fields.variant) || field("{map}", map))
            continue;
        out += pattern[i++];
    }
    return out;
}

std::string OutputNames::base() const {
    return expand("");
}

std::filesystem::path OutputNames::map_file(const std::filesystem::path& dir, const io::EncodedMap& map) const {
    return dir / (expand(map.suffix) + "." + map.extension);
}

} // namespace crackle::app
