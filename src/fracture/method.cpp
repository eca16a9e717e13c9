#include "fracture/method.hpp"

#include "core/error.hpp"

#include <stdexcept>

namespace crackle::fracture {

// Each method's folder provides its entry (method.cpp there).
MethodInfo fem_split_method();
MethodInfo fem_remove_method();
MethodInfo mass_spring_method();
MethodInfo graph_fem_method();

namespace {

std::vector<MethodInfo>& registry() {
    static std::vector<MethodInfo> all = [] {
        std::vector<MethodInfo> v{fem_split_method(), fem_remove_method(), mass_spring_method(), graph_fem_method()};
        for (MethodInfo& m : v)
            for (KeySpec& k : m.keys)
                k.group = m.name;
        return v;
    }();
    return all;
}

int generation = 0;

} // namespace

const std::vector<MethodInfo>& methods() {
    return registry();
}

int methods_generation() {
    return generation;
}

ScopedMethod::ScopedMethod(MethodInfo info) : m_name(info.name) {
    if (find_method(m_name)) throw std::logic_error("method " + m_name + " is registered twice");
    for (KeySpec& k : info.keys)
        k.group = info.name;
    registry().push_back(std::move(info));
    ++generation;
}

ScopedMethod::~ScopedMethod() {
    std::erase_if(registry(), [&](const MethodInfo& m) { return m.name == m_name; });
    ++generation;
}

const MethodInfo* find_method(const std::string& name) {
    for (const MethodInfo& m : methods())
        if (m.name == name) return &m;
    return nullptr;
}

std::vector<std::string> method_names() {
    std::vector<std::string> names;
    for (const MethodInfo& m : methods())
        names.push_back(m.name);
    return names;
}

std::unique_ptr<Method> make_method(const Settings& settings) {
    const std::string& name = settings.text("simulation.method");
    const MethodInfo* info = find_method(name);
    if (!info || !info->make) throw InputError("simulation.method = \"" + name + "\" is not available in this version");
    return info->make(settings);
}

} // namespace crackle::fracture
