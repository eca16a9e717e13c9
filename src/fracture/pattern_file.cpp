#include "fracture/pattern_file.hpp"

#include "core/error.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <type_traits>

namespace crackle::fracture {

namespace {

constexpr std::string_view MAGIC = "CRACKLE-PATTERN\n";

static_assert(std::endian::native == std::endian::little, "pattern files are little-endian");

class Writer {
public:
    template <class T> void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        const auto* p = reinterpret_cast<const std::uint8_t*>(&v);
        m_bytes.insert(m_bytes.end(), p, p + sizeof(T));
    }
    void count(std::size_t n) { put(static_cast<std::uint64_t>(n)); }
    void text(const std::string& s) {
        count(s.size());
        m_bytes.insert(m_bytes.end(), s.begin(), s.end());
    }
    void vec(const Vec3& v) {
        for (int i = 0; i < 3; ++i)
            put(v[i]);
    }
    template <class T> void array(const std::vector<T>& values) {
        count(values.size());
        for (const T& v : values)
            put(v);
    }
    std::vector<std::uint8_t>& bytes() { return m_bytes; }

private:
    std::vector<std::uint8_t> m_bytes;
};

/// Reads what Writer wrote, refusing to read past the end or to trust a count the rest of the
/// file cannot hold.
class Reader {
public:
    Reader(std::string_view bytes, std::string source) : m_bytes(bytes), m_source(std::move(source)) {}

    template <class T> T get() {
        static_assert(std::is_trivially_copyable_v<T>);
        need(sizeof(T), "a field");
        T v;
        std::memcpy(&v, m_bytes.data() + m_pos, sizeof(T));
        m_pos += sizeof(T);
        if constexpr (std::is_floating_point_v<T>)
            if (!std::isfinite(v)) fail("a number that is not finite at byte " + std::to_string(m_pos - sizeof(T)));
        return v;
    }
    /// A count of items of `item_bytes` each that the rest of the file must be able to hold.
    std::size_t count(std::size_t item_bytes, const char* what) {
        const auto n = get<std::uint64_t>();
        if (item_bytes > 0 && n > (m_bytes.size() - m_pos) / item_bytes)
            fail(std::string("a count of ") + std::to_string(n) + " " + what + " longer than the file");
        return static_cast<std::size_t>(n);
    }
    std::string text(const char* what) {
        const std::size_t n = count(1, what);
        std::string s(m_bytes.substr(m_pos, n));
        m_pos += n;
        return s;
    }
    Vec3 vec() {
        const double x = get<double>(), y = get<double>(), z = get<double>();
        return Vec3(x, y, z);
    }
    template <class T> std::vector<T> array(const char* what) {
        std::vector<T> v(count(sizeof(T), what));
        for (T& x : v)
            x = get<T>();
        return v;
    }
    std::size_t position() const { return m_pos; }
    [[noreturn]] void fail(const std::string& what) const {
        throw InputError(m_source, "not a readable crack pattern: " + what,
                         "re-create it with `crackle simulate PRESET --save FILE`");
    }

private:
    void need(std::size_t n, const char* what) const {
        if (m_bytes.size() - m_pos < n) fail(std::string("the file ends inside ") + what + " (truncated?)");
    }
    std::string_view m_bytes;
    std::string m_source;
    std::size_t m_pos = 0;
};

void write_body(Writer& w, const CrackPattern& p) {
    w.text(p.method);
    w.put(static_cast<std::uint32_t>(p.surface.kind()));
    const Vec2 size =
        p.surface.kind() == mesh::SurfaceKind::Sphere ? Vec2(p.surface.radius(), 0.0) : p.surface.period();
    w.put(size.x());
    w.put(size.y());

    const mesh::SurfaceMesh& m = p.mesh;
    w.put(static_cast<std::uint8_t>(m.periodic));
    w.put(m.period.x());
    w.put(m.period.y());
    w.vec(m.period_vectors[0]);
    w.vec(m.period_vectors[1]);
    w.count(m.positions.size());
    for (const Vec3& x : m.positions)
        w.vec(x);
    w.count(m.domain.size());
    for (const Vec2& x : m.domain) {
        w.put(x.x());
        w.put(x.y());
    }
    w.count(m.faces.size());
    for (const mesh::Face& f : m.faces)
        for (int k = 0; k < 3; ++k) {
            w.put(static_cast<std::uint32_t>(f.v[static_cast<std::size_t>(k)]));
            w.put(static_cast<std::int32_t>(f.offset[static_cast<std::size_t>(k)].x()));
            w.put(static_cast<std::int32_t>(f.offset[static_cast<std::size_t>(k)].y()));
        }

    w.count(p.deformed.size());
    for (const Vec3& x : p.deformed)
        w.vec(x);
    w.vec(p.deformed_period[0]);
    w.vec(p.deformed_period[1]);
    w.array(p.thickness);
    w.array(p.young_modulus);
    w.put(p.poisson_ratio);
    for (int i = 0; i < 9; ++i)
        w.put(p.growth_map.data()[i]);
    w.array(p.removed);
    w.array(p.fragment);
    w.put(static_cast<std::int32_t>(p.num_fragments));
    w.count(p.cracks.size());
    for (const CrackEdge& c : p.cracks) {
        w.put(static_cast<std::uint32_t>(c.face));
        w.put(static_cast<std::int32_t>(c.edge));
        w.put(c.opening);
        w.put(c.depth);
    }
    w.count(p.events.size());
    for (const Event& e : p.events) {
        w.put(e.time);
        w.vec(e.position);
        w.text(e.kind);
        w.put(e.ratio);
    }
    w.put(p.final_time);
    w.count(p.elements_initial);
    w.put(static_cast<std::uint8_t>(p.events_capped));
}

/// Reads the body and checks that every index points where it may.
CrackPattern read_body(Reader& r) {
    std::string method = r.text("characters of the method name");
    const auto kind = r.get<std::uint32_t>();
    if (kind > 2) r.fail("an unknown surface kind " + std::to_string(kind));
    mesh::SurfaceOptions so;
    so.kind = static_cast<mesh::SurfaceKind>(kind);
    so.size.x() = r.get<double>();
    so.size.y() = r.get<double>();
    if (!(so.size.x() > 0) || so.size.y() < 0) r.fail("a surface size that is not positive");
    CrackPattern p;
    p.method = std::move(method);
    p.surface = mesh::Surface(so);

    mesh::SurfaceMesh& m = p.mesh;
    m.periodic = r.get<std::uint8_t>() != 0;
    m.period.x() = r.get<double>();
    m.period.y() = r.get<double>();
    m.period_vectors[0] = r.vec();
    m.period_vectors[1] = r.vec();
    m.positions.resize(r.count(24, "vertices"), Vec3::Zero());
    for (Vec3& x : m.positions)
        x = r.vec();
    const std::size_t nv = m.positions.size();
    m.domain.resize(r.count(16, "domain points"), Vec2::Zero());
    if (!m.domain.empty() && m.domain.size() != nv) r.fail("domain points that do not match the vertices");
    for (Vec2& x : m.domain) {
        const double a = r.get<double>(), b = r.get<double>();
        x = Vec2(a, b);
    }
    m.faces.resize(r.count(36, "faces"), mesh::Face{{mesh::NO_VERTEX, mesh::NO_VERTEX, mesh::NO_VERTEX}});
    for (mesh::Face& f : m.faces)
        for (std::size_t k = 0; k < 3; ++k) {
            const auto v = r.get<std::uint32_t>();
            if (v >= nv) r.fail("a face corner naming vertex " + std::to_string(v) + " of " + std::to_string(nv));
            f.v[k] = mesh::vertex_id(v);
            const auto ox = r.get<std::int32_t>(), oy = r.get<std::int32_t>();
            if (std::abs(ox) > 2 || std::abs(oy) > 2 || (!m.periodic && (ox || oy)))
                r.fail("a periodic offset out of range");
            f.offset[k] = Vec2i(ox, oy);
        }
    const std::size_t nf = m.faces.size();

    p.deformed.resize(r.count(24, "deformed positions"), Vec3::Zero());
    for (Vec3& x : p.deformed)
        x = r.vec();
    p.deformed_period[0] = r.vec();
    p.deformed_period[1] = r.vec();
    p.thickness = r.array<double>("thicknesses");
    p.young_modulus = r.array<double>("moduli");
    p.poisson_ratio = r.get<double>();
    for (int i = 0; i < 9; ++i)
        p.growth_map.data()[i] = r.get<double>();
    p.removed = r.array<char>("removal flags");
    p.fragment = r.array<int>("fragment labels");
    p.num_fragments = r.get<std::int32_t>();
    if (p.deformed.size() != nv || p.thickness.size() != nv) r.fail("per-vertex arrays that do not match the mesh");
    if (p.removed.size() != nf || p.fragment.size() != nf || (!p.young_modulus.empty() && p.young_modulus.size() != nf))
        r.fail("per-face arrays that do not match the mesh");
    if (p.num_fragments < 0) r.fail("a negative fragment count");
    for (int label : p.fragment)
        if (label < -1 || label >= p.num_fragments) r.fail("a fragment label out of range");
    p.cracks.resize(r.count(24, "crack edges"));
    for (CrackEdge& c : p.cracks) {
        const auto face = r.get<std::uint32_t>();
        const auto edge = r.get<std::int32_t>();
        if (face >= nf || edge < 0 || edge > 2) r.fail("a crack edge outside the mesh");
        c.face = mesh::face_id(face);
        c.edge = edge;
        c.opening = r.get<double>();
        c.depth = r.get<double>();
    }
    p.events.resize(r.count(48, "events"));
    for (Event& e : p.events) {
        e.time = r.get<double>();
        e.position = r.vec();
        e.kind = r.text("characters of an event kind");
        e.ratio = r.get<double>();
    }
    p.final_time = r.get<double>();
    p.elements_initial = r.count(0, "");
    p.events_capped = r.get<std::uint8_t>() != 0;

    try {
        m.rebuild_adjacency();
    } catch (const InvariantError& e) {
        r.fail(std::string("its mesh is not a surface: ") + e.what());
    }
    if (const std::string problem = m.validate(); !problem.empty()) r.fail("its mesh is not valid: " + problem);
    return p;
}

/// Checks the magic, the version and the checksum; returns the header text and the reader,
/// positioned at the body.
Reader open(std::string_view bytes, const std::string& source, std::string& header_text) {
    Reader r(bytes, source);
    if (bytes.size() < MAGIC.size() || bytes.substr(0, MAGIC.size()) != MAGIC)
        throw InputError(source, "not a crackle pattern file (no CRACKLE-PATTERN signature)",
                         "give a file written by `crackle simulate PRESET --save FILE`");
    for (std::size_t i = 0; i < MAGIC.size(); ++i)
        r.get<char>();
    const auto version = r.get<std::uint32_t>();
    if (version != PATTERN_FORMAT_VERSION)
        throw InputError(source,
                         "pattern format version " + std::to_string(version) + ", this crackle reads version "
                             + std::to_string(PATTERN_FORMAT_VERSION),
                         "re-create it with this crackle: `crackle simulate PRESET --save FILE`");
    header_text = r.text("characters of the header");
    return r;
}

} // namespace

std::uint64_t fnv1a64(std::string_view bytes, std::uint64_t seed) {
    std::uint64_t h = seed;
    for (const char c : bytes) {
        h ^= static_cast<std::uint8_t>(c);
        h *= 0x100000001b3ull;
    }
    return h;
}

std::vector<std::uint8_t> encode_pattern(const CrackPattern& pattern, const Json& header) {
    Writer w;
    for (const char c : MAGIC)
        w.put(c);
    w.put(PATTERN_FORMAT_VERSION);
    w.text(header.dump());
    write_body(w, pattern);
    const auto& b = w.bytes();
    w.put(fnv1a64(std::string_view(reinterpret_cast<const char*>(b.data()), b.size())));
    return std::move(w.bytes());
}

Json pattern_header(std::string_view bytes, const std::string& source) {
    std::string text;
    open(bytes, source, text);
    return Json::parse(text, source + " (header)");
}

PatternFile decode_pattern(std::string_view bytes, const std::string& source) {
    std::string text;
    Reader whole = open(bytes, source, text); // signature and version first: the clearest message
    if (bytes.size() < whole.position() + 8) whole.fail("the file ends before its checksum (truncated?)");
    const std::string_view content = bytes.substr(0, bytes.size() - 8);
    std::uint64_t stored = 0;
    std::memcpy(&stored, bytes.data() + content.size(), 8);
    if (fnv1a64(content) != stored) whole.fail("its checksum does not match (truncated or changed since written)");
    Reader body = open(content, source, text);
    PatternFile f;
    f.header = Json::parse(text, source + " (header)");
    f.pattern = read_body(body);
    if (body.position() != content.size()) body.fail("bytes left over after the pattern");
    return f;
}

} // namespace crackle::fracture
