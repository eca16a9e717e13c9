#pragma once
/// @file Strong element ids (style guide §3): a FaceId never indexes vertices.

#include <cstdint>
#include <limits>
#include <vector>

namespace crackle::mesh {

enum class VertexId : std::uint32_t {};
enum class FaceId : std::uint32_t {};

constexpr FaceId NO_FACE = FaceId{std::numeric_limits<std::uint32_t>::max()};
constexpr VertexId NO_VERTEX = VertexId{std::numeric_limits<std::uint32_t>::max()};

/// The array index behind an id.
template <typename Id> constexpr std::size_t ix(Id id) {
    return static_cast<std::size_t>(id);
}
constexpr VertexId vertex_id(std::size_t i) {
    return VertexId{static_cast<std::uint32_t>(i)};
}
constexpr FaceId face_id(std::size_t i) {
    return FaceId{static_cast<std::uint32_t>(i)};
}

/// A per-element array that only takes its own id type as index.
template <typename Id, typename T> class IdVector {
public:
    IdVector() = default;
    explicit IdVector(std::size_t n, const T& value = T()) : m_data(n, value) {}
    T& operator[](Id id) { return m_data[ix(id)]; }
    const T& operator[](Id id) const { return m_data[ix(id)]; }
    std::size_t size() const { return m_data.size(); }
    bool empty() const { return m_data.empty(); }
    void resize(std::size_t n, const T& value = T()) { m_data.resize(n, value); }
    void push_back(const T& value) { m_data.push_back(value); }
    auto begin() { return m_data.begin(); }
    auto end() { return m_data.end(); }
    auto begin() const { return m_data.begin(); }
    auto end() const { return m_data.end(); }
    std::vector<T>& raw() { return m_data; }
    const std::vector<T>& raw() const { return m_data; }

private:
    std::vector<T> m_data;
};

} // namespace crackle::mesh
