/// @file Json::parse: a strict recursive-descent reader for the JSON crackle writes itself
/// (reports, the study's reference) and for tools that hand it JSON.

#include "core/error.hpp"
#include "core/json.hpp"

#include <cstdlib>

namespace crackle {

namespace {

class Parser {
public:
    Parser(std::string_view text, const std::string& source) : m_text(text), m_source(source) {}

    Json document() {
        Json v = value(0);
        skip_space();
        if (m_pos != m_text.size()) fail("unexpected text after the value");
        return v;
    }

private:
    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(m_source, "invalid JSON at byte " + std::to_string(m_pos) + ": " + what,
                         "the file must be JSON as crackle writes it");
    }

    void skip_space() {
        while (m_pos < m_text.size()
               && (m_text[m_pos] == ' ' || m_text[m_pos] == '\n' || m_text[m_pos] == '\r' || m_text[m_pos] == '\t'))
            ++m_pos;
    }

    bool take(char c) {
        skip_space();
        if (m_pos < m_text.size() && m_text[m_pos] == c) {
            ++m_pos;
            return true;
        }
        return false;
    }

    void expect(char c) {
        if (!take(c)) fail(std::string("expected '") + c + "'");
    }

    bool word(std::string_view w) {
        if (m_text.substr(m_pos, w.size()) != w) return false;
        m_pos += w.size();
        return true;
    }

    Json value(int depth) {
        if (depth > 256) fail("nested too deeply");
        skip_space();
        if (m_pos >= m_text.size()) fail("unexpected end");
        const char c = m_text[m_pos];
        if (c == '{') return object(depth);
        if (c == '[') return array(depth);
        if (c == '"') return Json(string());
        if (word("true")) return Json(true);
        if (word("false")) return Json(false);
        if (word("null")) return Json();
        return number();
    }

    Json object(int depth) {
        expect('{');
        Json o = Json::object();
        if (take('}')) return o;
        do {
            skip_space();
            if (m_pos >= m_text.size() || m_text[m_pos] != '"') fail("expected a member name");
            const std::string key = string();
            expect(':');
            o[key] = value(depth + 1);
        } while (take(','));
        expect('}');
        return o;
    }

    Json array(int depth) {
        expect('[');
        Json a = Json::array();
        if (take(']')) return a;
        do
            a.push_back(value(depth + 1));
        while (take(','));
        expect(']');
        return a;
    }

    std::string string() {
        ++m_pos; // opening quote
        std::string s;
        while (true) {
            if (m_pos >= m_text.size()) fail("unterminated string");
            const char c = m_text[m_pos++];
            if (c == '"') return s;
            if (static_cast<unsigned char>(c) < 0x20) fail("control character in a string");
            if (c != '\\') {
                s += c;
                continue;
            }
            if (m_pos >= m_text.size()) fail("unterminated escape");
            const char e = m_text[m_pos++];
            switch (e) {
            case '"':
            case '\\':
            case '/':
                s += e;
                break;
            case 'b':
                s += '\b';
                break;
            case 'f':
                s += '\f';
                break;
            case 'n':
                s += '\n';
                break;
            case 'r':
                s += '\r';
                break;
            case 't':
                s += '\t';
                break;
            case 'u':
                append_utf8(s, hex4());
                break;
            default:
                fail("unknown escape");
            }
        }
    }

    unsigned hex4() {
        if (m_pos + 4 > m_text.size()) fail("short \\u escape");
        unsigned v = 0;
        for (int i = 0; i < 4; ++i) {
            const char h = m_text[m_pos++];
            v <<= 4;
            if (h >= '0' && h <= '9')
                v |= unsigned(h - '0');
            else if (h >= 'a' && h <= 'f')
                v |= unsigned(h - 'a' + 10);
            else if (h >= 'A' && h <= 'F')
                v |= unsigned(h - 'A' + 10);
            else
                fail("bad hex digit in \\u escape");
        }
        return v;
    }

    void append_utf8(std::string& s, unsigned cp) {
        if (cp >= 0xD800 && cp <= 0xDBFF) { // a surrogate pair
            if (!word("\\u")) fail("lone high surrogate");
            const unsigned lo = hex4();
            if (lo < 0xDC00 || lo > 0xDFFF) fail("bad low surrogate");
            cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
        } else if (cp >= 0xDC00 && cp <= 0xDFFF) {
            fail("lone low surrogate");
        }
        if (cp < 0x80) {
            s += char(cp);
        } else if (cp < 0x800) {
            s += char(0xC0 | (cp >> 6));
            s += char(0x80 | (cp & 0x3F));
        } else if (cp < 0x10000) {
            s += char(0xE0 | (cp >> 12));
            s += char(0x80 | ((cp >> 6) & 0x3F));
            s += char(0x80 | (cp & 0x3F));
        } else {
            s += char(0xF0 | (cp >> 18));
            s += char(0x80 | ((cp >> 12) & 0x3F));
            s += char(0x80 | ((cp >> 6) & 0x3F));
            s += char(0x80 | (cp & 0x3F));
        }
    }

    Json number() {
        const std::size_t start = m_pos;
        bool integral = true;
        if (m_pos < m_text.size() && m_text[m_pos] == '-') ++m_pos;
        auto digits = [&] {
            const std::size_t d0 = m_pos;
            while (m_pos < m_text.size() && m_text[m_pos] >= '0' && m_text[m_pos] <= '9')
                ++m_pos;
            if (m_pos == d0) fail("expected a value");
        };
        digits();
        if (m_pos < m_text.size() && m_text[m_pos] == '.') {
            integral = false;
            ++m_pos;
            digits();
        }
        if (m_pos < m_text.size() && (m_text[m_pos] == 'e' || m_text[m_pos] == 'E')) {
            integral = false;
            ++m_pos;
            if (m_pos < m_text.size() && (m_text[m_pos] == '+' || m_text[m_pos] == '-')) ++m_pos;
            digits();
        }
        const std::string token(m_text.substr(start, m_pos - start));
        if (integral && token.size() <= 18) return Json(std::strtoll(token.c_str(), nullptr, 10));
        return Json(std::strtod(token.c_str(), nullptr));
    }

    std::string_view m_text;
    const std::string& m_source;
    std::size_t m_pos = 0;
};

} // namespace

Json Json::parse(std::string_view text, const std::string& source) {
    return Parser(text, source).document();
}

} // namespace crackle
