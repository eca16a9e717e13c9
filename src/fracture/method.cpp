#include "fracture/method.hpp"

#include "core/error.hpp"

namespace crackle::fracture {

// Each method's folder provides its entry (method.cpp there).
MethodInfo fem_split_method();
MethodInfo fem_remove_method();
MethodInfo mass_spring_method();
MethodInfo graph_fem_method();

const std::vector<MethodInfo>& methods() {
    static const std::vector<MethodInfo> all = [] {
        std::vector<MethodInfo> v{fem_split_method(), fem_remove_method(), mass_spring_method(), graph_fem_method()};
        for (MethodInfo& m : v)
            for (KeySpec& k : m.keys)
                k.group = m.name;
        return v;
    }();
    return all;
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
