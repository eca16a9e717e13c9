#include "core/json.hpp"

#include "core/error.hpp"

#include <cmath>
#include <cstdio>

namespace crackle {

Json& Json::operator[](const std::string& key) {
    if (std::holds_alternative<std::nullptr_t>(m_value)) m_value = Object{};
    auto& obj = std::get<Object>(m_value);
    for (auto& [k, v] : obj)
        if (k == key) return v;
    obj.emplace_back(key, Json());
    return obj.back().second;
}

const Json* Json::find(const std::string& key) const {
    if (!is_object()) return nullptr;
    for (const auto& [k, v] : std::get<Object>(m_value))
        if (k == key) return &v;
    return nullptr;
}

void Json::push_back(Json v) {
    if (std::holds_alternative<std::nullptr_t>(m_value)) m_value = Array{};
    std::get<Array>(m_value).push_back(std::move(v));
}

const Json::Object& Json::members() const {
    static const Object none;
    const Object* o = std::get_if<Object>(&m_value);
    return o ? *o : none;
}

double Json::as_number() const {
    if (const auto* d = std::get_if<double>(&m_value)) return *d;
    if (const auto* i = std::get_if<std::int64_t>(&m_value)) return static_cast<double>(*i);
    CRACKLE_ASSERT(false, "JSON value is not a number");
}

const Json::Array& Json::elements() const {
    static const Array none;
    const Array* a = std::get_if<Array>(&m_value);
    return a ? *a : none;
}

const std::string& Json::as_string() const {
    static const std::string none;
    const std::string* s = std::get_if<std::string>(&m_value);
    return s ? *s : none;
}

namespace {

/// Bytes of the valid UTF-8 sequence starting at s[i] (RFC 3629: no overlongs, no surrogates,
/// nothing past U+10FFFF), or 0 when there is none.
std::size_t utf8_length(const std::string& s, std::size_t i) {
    const auto byte = [&](std::size_t k) { return k < s.size() ? static_cast<unsigned char>(s[k]) : 0u; };
    const unsigned b0 = byte(i);
    std::size_t n = 0;
    unsigned lo = 0x80, hi = 0xBF; // the second byte's range
    if (b0 >= 0xC2 && b0 <= 0xDF)
        n = 2;
    else if (b0 >= 0xE0 && b0 <= 0xEF) {
        n = 3;
        if (b0 == 0xE0) lo = 0xA0;
        if (b0 == 0xED) hi = 0x9F;
    } else if (b0 >= 0xF0 && b0 <= 0xF4) {
        n = 4;
        if (b0 == 0xF0) lo = 0x90;
        if (b0 == 0xF4) hi = 0x8F;
    } else
        return 0;
    if (byte(i + 1) < lo || byte(i + 1) > hi) return 0;
    for (std::size_t k = 2; k < n; ++k)
        if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
    return n;
}

/// A JSON string; bytes that are not UTF-8 (a file name with byte 0xFF) become U+FFFD, so a
/// report is always valid UTF-8.
void escape(std::string& out, const std::string& s) {
    out += '"';
    for (std::size_t i = 0; i < s.size(); ++i) {
        const char c = s[i];
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x80) {
            const std::size_t n = utf8_length(s, i);
            if (n == 0) {
                out += "\ufffd";
            } else {
                out.append(s, i, n);
                i += n - 1;
            }
            continue;
        }
        switch (c) {
        case '"':
            out += "\\\"";
            break;
        case '\\':
            out += "\\\\";
            break;
        case '\n':
            out += "\\n";
            break;
        case '\t':
            out += "\\t";
            break;
        case '\r':
            out += "\\r";
            break;
        default:
            if (u < 0x20) {
                char buf[8];
                std::snprintf(buf, sizeof buf, "\\u%04x", u);
                out += buf;
            } else {
                out += c;
            }
        }
    }
    out += '"';
}
} // namespace

void Json::dump_to(std::string& out, int indent) const {
    const std::string pad(static_cast<size_t>(indent + 2), ' ');
    const std::string close_pad(static_cast<size_t>(indent), ' ');
    if (std::holds_alternative<std::nullptr_t>(m_value)) {
        out += "null";
    } else if (const auto* b = std::get_if<bool>(&m_value)) {
        out += *b ? "true" : "false";
    } else if (const auto* i = std::get_if<std::int64_t>(&m_value)) {
        out += std::to_string(*i);
    } else if (const auto* d = std::get_if<double>(&m_value)) {
        if (!std::isfinite(*d)) {
            out += "null";
        } else {
            char buf[32];
            std::snprintf(buf, sizeof buf, "%.10g", *d);
            out += buf;
        }
    } else if (const auto* s = std::get_if<std::string>(&m_value)) {
        escape(out, *s);
    } else if (const auto* a = std::get_if<Array>(&m_value)) {
        if (a->empty()) {
            out += "[]";
            return;
        }
        out += "[\n";
        for (size_t k = 0; k < a->size(); ++k) {
            out += pad;
            (*a)[k].dump_to(out, indent + 2);
            out += k + 1 < a->size() ? ",\n" : "\n";
        }
        out += close_pad + "]";
    } else if (const auto* o = std::get_if<Object>(&m_value)) {
        if (o->empty()) {
            out += "{}";
            return;
        }
        out += "{\n";
        for (size_t k = 0; k < o->size(); ++k) {
            out += pad;
            escape(out, (*o)[k].first);
            out += ": ";
            (*o)[k].second.dump_to(out, indent + 2);
            out += k + 1 < o->size() ? ",\n" : "\n";
        }
        out += close_pad + "}";
    }
}

std::string Json::dump() const {
    std::string out;
    dump_to(out, 0);
    out += '\n';
    return out;
}

} // namespace crackle
