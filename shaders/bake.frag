// The simulated height of one texel (anti-aliased); the maps are shaped from it on the CPU
// (render/relief.cpp, render/shading.cpp).
centroid in float v_height;
flat in int v_fragment;
centroid in float v_crack;
centroid in float v_weight;
centroid in float v_age;

layout(location = 0) out vec4 o_height; // r: height (m)

void main()
{
    o_height = vec4(v_height, 0.0, 0.0, 1.0);
}
