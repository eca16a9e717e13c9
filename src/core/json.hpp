#pragma once
/// @file A small ordered JSON value for reports (`--json`). Keys keep insertion order so
/// reports diff cleanly between runs.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

namespace crackle {

class Json {
public:
    using Array = std::vector<Json>;
    using Object = std::vector<std::pair<std::string, Json>>;

    Json() : m_value(nullptr) {}
    Json(std::nullptr_t) : m_value(nullptr) {}
    Json(bool b) : m_value(b) {}
    Json(int v) : m_value(static_cast<std::int64_t>(v)) {}
    Json(long v) : m_value(static_cast<std::int64_t>(v)) {}
    Json(long long v) : m_value(static_cast<std::int64_t>(v)) {}
    Json(unsigned v) : m_value(static_cast<std::int64_t>(v)) {}
    Json(unsigned long v) : m_value(static_cast<std::int64_t>(v)) {}
    Json(unsigned long long v) : m_value(static_cast<std::int64_t>(v)) {}
    Json(double v) : m_value(v) {}
    Json(const char* s) : m_value(std::string(s)) {}
    Json(std::string s) : m_value(std::move(s)) {}
    Json(Array a) : m_value(std::move(a)) {}
    Json(Object o) : m_value(std::move(o)) {}

    static Json object() { return Json(Object{}); }
    static Json array() { return Json(Array{}); }

    /// Object member access; inserts a null member when absent.
    Json& operator[](const std::string& key);
    const Json* find(const std::string& key) const;
    void push_back(Json v);

    bool is_object() const { return std::holds_alternative<Object>(m_value); }
    /// The members of an object, in order (an empty list for anything else).
    const Object& members() const;
    double as_number() const;
    bool is_number() const {
        return std::holds_alternative<double>(m_value) || std::holds_alternative<std::int64_t>(m_value);
    }
    bool is_integer() const { return std::holds_alternative<std::int64_t>(m_value); }
    bool is_string() const { return std::holds_alternative<std::string>(m_value); }
    bool is_array() const { return std::holds_alternative<Array>(m_value); }
    bool is_bool() const { return std::holds_alternative<bool>(m_value); }
    bool as_bool() const { return is_bool() && std::get<bool>(m_value); }
    /// The elements of an array (an empty list for anything else).
    const Array& elements() const;
    /// The text of a string ("" for anything else).
    const std::string& as_string() const;

    /// Parses JSON text (RFC 8259; numbers without a fraction or exponent that fit become
    /// integers). @throws InputError naming `source` and the byte offset of the first error.
    static Json parse(std::string_view text, const std::string& source);

    /// Pretty-printed with two-space indentation and a trailing newline at top level.
    std::string dump() const;

private:
    void dump_to(std::string& out, int indent) const;
    std::variant<std::nullptr_t, bool, std::int64_t, double, std::string, Array, Object> m_value;
};

} // namespace crackle
