// Height, normal, albedo and material channels of one texel.
centroid in vec2 v_uv;
centroid in float v_height;
centroid in vec3 v_normal;
flat in int v_fragment;
centroid in float v_crack;

uniform vec3 u_color;            // linear RGB of the top surface
uniform vec3 u_crack_color;      // linear RGB of crack walls and floor
uniform float u_color_variation; // per-piece brightness/hue variation, 0..1
uniform float u_roughness;
uniform float u_roughness_variation;
uniform float u_max_height;
uniform uint u_seed;
uniform vec2 u_grain_cells;     // tiling noise cells across the tile (u, v)
uniform float u_grain;          // strength of the surface grain, 0..1

layout(location = 0) out vec4 o_height;    // r: height (m)
layout(location = 1) out vec4 o_normal;    // xyz: (n + 1) / 2 in the texture frame
layout(location = 2) out vec4 o_color;     // linear RGB (an sRGB target encodes it)
layout(location = 3) out vec4 o_material;  // r: crack mask, g: roughness

void main()
{
    vec3 n = normalize(v_normal);
    o_height = vec4(v_height, 0.0, 0.0, 1.0);
    o_normal = vec4(0.5 * n + 0.5, 1.0);

    // Per-piece variation: brightness and a little hue shift, from the piece label.
    float r0 = v_fragment >= 0 ? crackle_random(v_fragment, 0u, u_seed) : 0.5;
    float r1 = v_fragment >= 0 ? crackle_random(v_fragment, 1u, u_seed) : 0.5;
    float r2 = v_fragment >= 0 ? crackle_random(v_fragment, 2u, u_seed) : 0.5;
    vec3 tint = vec3(1.0) + u_color_variation * vec3(r1 - 0.5, r2 - 0.5, 0.5 - r1) * 0.6;
    float brightness = 1.0 + u_color_variation * (r0 - 0.5);
    float grain = 1.0 + u_grain * (2.0 * crackle_fbm(v_uv, ivec2(u_grain_cells + 0.5), u_seed) - 1.0);
    vec3 top = u_color * tint * brightness * grain;
    // Crack interiors darken with depth below the surface.
    float depth_shade = clamp(v_height / max(u_max_height, 1e-9), 0.0, 1.0);
    vec3 crack = u_crack_color * mix(0.6, 1.0, depth_shade) * (1.0 + 0.5 * u_grain * (crackle_fbm(v_uv, ivec2(u_grain_cells + 0.5) * 2, u_seed + 7u) - 0.5));
    o_color = vec4(mix(top, crack, v_crack), 1.0);

    float rough = u_roughness + u_roughness_variation * (r0 - 0.5) + 0.15 * v_crack;
    o_material = vec4(v_crack, clamp(rough, 0.0, 1.0), 0.0, 1.0);
}
