#include "io/manifest.hpp"

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json.hpp"

#include <toml++/toml.h>

#include <cstdio>
#include <sstream>

namespace crackle::io {

namespace {

const char* const KEYS_HELP = "a variant takes preset, set, seed, seeds and name";

std::string number_text(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    std::string s = buf;
    if (s.find_first_of(".eEn") == std::string::npos) s += ".0"; // a float stays a float
    return s;
}

std::string quoted(const std::string& s) {
    std::string out = "\"";
    for (const char c : s) {
        if (c == '"' || c == '\\') out += '\\';
        out += c;
    }
    return out + "\"";
}

/// A JSON value as the TOML text `--set` takes.
std::string override_text(const Json& v, const std::string& where) {
    if (v.is_integer()) return std::to_string(static_cast<long long>(v.as_number()));
    if (v.is_number()) return number_text(v.as_number());
    if (v.is_bool()) return v.as_bool() ? "true" : "false";
    if (v.is_string()) return quoted(v.as_string());
    if (v.is_array()) {
        std::string s = "[";
        for (const Json& e : v.elements())
            s += (s.size() > 1 ? "," : "") + override_text(e, where);
        return s + "]";
    }
    throw InputError(where, "an override value that is neither a number, a text, true/false nor a list",
                     "write it as in a preset, e.g. \"bake.color\": [0.5, 0.4, 0.3]");
}

ManifestEntry entry_from_json(const Json& j, const std::string& where) {
    if (!j.is_object())
        throw InputError(where, "not a JSON object", "write one {\"preset\": \"mud\", \"seed\": 3} per line");
    ManifestEntry e;
    e.where = where;
    for (const auto& [key, v] : j.members()) {
        if (key == "preset" && v.is_string()) {
            e.preset = v.as_string();
        } else if (key == "name" && v.is_string()) {
            e.name = v.as_string();
        } else if (key == "seeds" && v.is_string()) {
            e.seeds = v.as_string();
        } else if (key == "seed" && v.is_integer() && v.as_number() >= 0) {
            e.seed = static_cast<std::int64_t>(v.as_number());
        } else if (key == "set" && v.is_object()) {
            for (const auto& [k, value] : v.members())
                e.overrides.push_back(k + "=" + override_text(value, where));
        } else if (key == "set" && v.is_array()) {
            for (const Json& item : v.elements()) {
                if (!item.is_string())
                    throw InputError(where, "'set' lists something other than \"key=value\" texts",
                                     "write \"set\": [\"bake.size=512\"] or \"set\": {\"bake.size\": 512}");
                e.overrides.push_back(item.as_string());
            }
        } else {
            const bool known = key == "preset" || key == "name" || key == "seeds" || key == "seed" || key == "set";
            throw InputError(
                where, known ? "'" + key + "' has the wrong type" : "unknown key '" + key + "'",
                std::string(KEYS_HELP)
                    + " (preset, name: text; seed: a whole number ≥ 0; seeds: a text like \"1-10\"; set: a "
                      "table or a list of \"key=value\")");
        }
    }
    if (e.preset.empty())
        throw InputError(where, "no preset", "add \"preset\": \"mud\" (a built-in name or a .toml path)");
    if (e.seed >= 0 && !e.seeds.empty())
        throw InputError(where, "both seed and seeds", "give one seed or a seed list, not both");
    return e;
}

/// TOML → the same JSON shape, so one reader checks both formats.
Json json_of(const toml::node& node) {
    if (const auto* t = node.as_table()) {
        Json o = Json::object();
        for (const auto& [k, v] : *t)
            o[std::string(k.str())] = json_of(v);
        return o;
    }
    if (const auto* a = node.as_array()) {
        Json arr = Json::array();
        for (const auto& v : *a)
            arr.push_back(json_of(v));
        return arr;
    }
    if (const auto* i = node.as_integer()) return static_cast<long long>(i->get());
    if (const auto* d = node.as_floating_point()) return d->get();
    if (const auto* b = node.as_boolean()) return b->get();
    if (const auto* s = node.as_string()) return s->get();
    return Json();
}

std::vector<ManifestEntry> read_jsonl(const std::string& text, const std::string& file) {
    std::vector<ManifestEntry> entries;
    std::istringstream in(text);
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        const std::string where = file + ":" + std::to_string(number);
        entries.push_back(entry_from_json(Json::parse(line, where), where));
    }
    return entries;
}

std::vector<ManifestEntry> read_toml(const std::string& text, const std::string& file) {
    toml::table table;
    try {
        table = toml::parse(std::string_view(text), std::string_view(file));
    } catch (const toml::parse_error& e) {
        throw InputError(file + ":" + std::to_string(e.source().begin.line), std::string(e.description()),
                         "fix the TOML syntax; see docs/farm.md for the manifest format");
    }
    std::vector<ManifestEntry> entries;
    for (const auto& [key, node] : table) {
        const std::string where = file + ":" + std::to_string(node.source().begin.line);
        if (key.str() != "variant" || !node.is_array_of_tables())
            throw InputError(where, "unknown top-level key '" + std::string(key.str()) + "'",
                             "write each variant as a [[variant]] table");
        for (const auto& v : *node.as_array()) {
            const std::string at = file + ":" + std::to_string(v.source().begin.line);
            entries.push_back(entry_from_json(json_of(v), at));
        }
    }
    return entries;
}

} // namespace

std::vector<ManifestEntry> read_manifest_entries(const std::filesystem::path& path) {
    const std::string text = read_file(path, "manifest");
    const std::string ext = path.extension().string(), file = path.string();
    std::vector<ManifestEntry> entries;
    if (ext == ".jsonl" || ext == ".ndjson" || ext == ".json")
        entries = read_jsonl(text, file);
    else if (ext == ".toml")
        entries = read_toml(text, file);
    else
        throw InputError(file, "a manifest must be JSON Lines (.jsonl) or TOML (.toml)", "rename it or convert it");
    if (entries.empty()) throw InputError(file, "the manifest lists no variants", "add at least one variant");
    // Relative preset files are relative to the manifest.
    for (ManifestEntry& e : entries) {
        const std::filesystem::path p(e.preset);
        if (p.extension() == ".toml" && p.is_relative() && std::filesystem::exists(path.parent_path() / p))
            e.preset = (path.parent_path() / p).string();
    }
    return entries;
}

} // namespace crackle::io
