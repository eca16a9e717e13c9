#pragma once
/// @file Settings: the spec of a configuration key (type, default, unit, range, one-line
/// description) and read access to resolved values. io's presets implement `Settings`; each
/// fracture method declares its own keys and maps its typed options from them, so a method
/// lives in one folder.

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

namespace crackle {

enum class ValueType { Float, Int, Bool, String, Enum, FloatArray };

using Value = std::variant<double, std::int64_t, bool, std::string, std::vector<double>>;

struct KeySpec {
    std::string section; ///< "material", "variation.thickness"
    std::string key;     ///< "young_modulus"
    ValueType type = ValueType::Float;
    Value default_value;
    std::string unit;                 ///< "Pa", "m", "1/time", "" when dimensionless
    std::string description;          ///< one line: what it does, and how it looks
    double min = -1e300, max = 1e300; ///< numeric range (each element for arrays)
    bool min_exclusive = false, max_exclusive = false;
    std::vector<std::string> choices;   ///< Enum values
    int min_length = 0, max_length = 0; ///< FloatArray lengths
    std::string group;                  ///< who reads it, within its section ("" = everyone; "fem-split")
    bool allows_auto = false;           ///< a numeric key that also takes the string "auto"

    std::string name() const { return section + "." + key; }
};

/// Builders of key specs (ranges inclusive unless said otherwise).
namespace keys {
KeySpec number(std::string section, std::string key, double def, std::string unit, double lo, double hi,
               std::string description, bool lo_excl = false, bool hi_excl = false);
KeySpec integer(std::string section, std::string key, std::int64_t def, std::string unit, double lo, double hi,
                std::string description);
/// An integer key that also takes "auto" (the program chooses; Settings::is_auto).
KeySpec integer_or_auto(std::string section, std::string key, std::string unit, double lo, double hi,
                        std::string description);
/// A number key that also takes "auto", its default.
KeySpec number_or_auto(std::string section, std::string key, std::string unit, double lo, double hi,
                       std::string description);
KeySpec choice(std::string section, std::string key, std::string def, std::vector<std::string> choices,
               std::string description);
KeySpec array(std::string section, std::string key, std::vector<double> def, int min_len, int max_len, std::string unit,
              double lo, double hi, std::string description, bool lo_excl = false);
KeySpec boolean(std::string section, std::string key, bool def, std::string description);
KeySpec text(std::string section, std::string key, std::string def, std::string description);
} // namespace keys

/// Resolved values by full key name ("simulation.min_angle"). Asking for a key the schema
/// does not have, or with the wrong type, is a programming error.
class Settings {
public:
    virtual ~Settings() = default;
    virtual double number(const std::string& key) const = 0;
    virtual std::int64_t integer(const std::string& key) const = 0;
    virtual bool flag(const std::string& key) const = 0;
    virtual const std::string& text(const std::string& key) const = 0;
    virtual const std::vector<double>& numbers(const std::string& key) const = 0;
    /// True when an integer_or_auto or number_or_auto key holds "auto" (integer() and number()
    /// must not be asked then).
    virtual bool is_auto(const std::string& key) const = 0;
};

} // namespace crackle
