#include "core/settings.hpp"

namespace crackle::keys {

KeySpec number(std::string section, std::string key, double def, std::string unit, double lo, double hi,
               std::string description, bool lo_excl, bool hi_excl) {
    KeySpec s;
    s.section = std::move(section);
    s.key = std::move(key);
    s.type = ValueType::Float;
    s.default_value = def;
    s.unit = std::move(unit);
    s.min = lo;
    s.max = hi;
    s.min_exclusive = lo_excl;
    s.max_exclusive = hi_excl;
    s.description = std::move(description);
    return s;
}

KeySpec integer(std::string section, std::string key, std::int64_t def, std::string unit, double lo, double hi,
                std::string description) {
    KeySpec s = number(std::move(section), std::move(key), 0, std::move(unit), lo, hi, std::move(description));
    s.type = ValueType::Int;
    s.default_value = def;
    return s;
}

KeySpec integer_or_auto(std::string section, std::string key, std::string unit, double lo, double hi,
                        std::string description) {
    KeySpec s = integer(std::move(section), std::move(key), 0, std::move(unit), lo, hi, std::move(description));
    s.default_value = std::string("auto");
    s.allows_auto = true;
    return s;
}

KeySpec number_or_auto(std::string section, std::string key, std::string unit, double lo, double hi,
                       std::string description) {
    KeySpec s = number(std::move(section), std::move(key), 0, std::move(unit), lo, hi, std::move(description));
    s.default_value = std::string("auto");
    s.allows_auto = true;
    return s;
}

KeySpec choice(std::string section, std::string key, std::string def, std::vector<std::string> choices,
               std::string description) {
    KeySpec s;
    s.section = std::move(section);
    s.key = std::move(key);
    s.type = ValueType::Enum;
    s.default_value = std::move(def);
    s.choices = std::move(choices);
    s.description = std::move(description);
    return s;
}

KeySpec array(std::string section, std::string key, std::vector<double> def, int min_len, int max_len, std::string unit,
              double lo, double hi, std::string description, bool lo_excl) {
    KeySpec s = number(std::move(section), std::move(key), 0, std::move(unit), lo, hi, std::move(description), lo_excl);
    s.type = ValueType::FloatArray;
    s.default_value = std::move(def);
    s.min_length = min_len;
    s.max_length = max_len;
    return s;
}

KeySpec boolean(std::string section, std::string key, bool def, std::string description) {
    KeySpec s;
    s.section = std::move(section);
    s.key = std::move(key);
    s.type = ValueType::Bool;
    s.default_value = def;
    s.description = std::move(description);
    return s;
}

KeySpec text(std::string section, std::string key, std::string def, std::string description) {
    KeySpec s;
    s.section = std::move(section);
    s.key = std::move(key);
    s.type = ValueType::String;
    s.default_value = std::move(def);
    s.description = std::move(description);
    return s;
}

} // namespace crackle::keys
