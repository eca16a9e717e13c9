// Orthographic projection of texture space: (u, v) → clip space, height → depth.
layout(location = 0) in vec2 a_uv;
layout(location = 1) in float a_height;   // m, before curl and lip rounding
layout(location = 2) in float a_fragment; // piece label + 1; 0 on the crack floor
layout(location = 3) in float a_crack;    // 1 on walls, floor and lips
layout(location = 4) in float a_weight;   // crack weight: 1 = a first, wide crack
layout(location = 5) in float a_age;      // crack age: 1 = the first crack, 0 = the last

uniform vec4 u_tile;           // (u0, v0, u1, v1): the part of texture space this tile shows
uniform float u_max_height;    // m; maps height to depth
uniform vec2 u_offsets[9];     // periodic copies, one per instance

// Centroid interpolation: with multisampling a pixel whose centre lies outside a triangle that
// covers some of its samples would otherwise extrapolate the triangle's values to the centre;
// along steep crack walls that gave heights of -16..+20 mm on a 14 mm layer.
centroid out float v_height;
flat out int v_fragment;
centroid out float v_crack;
centroid out float v_weight;
centroid out float v_age;

void main()
{
    vec2 uv = a_uv + u_offsets[gl_InstanceID];
    vec2 ndc = 2.0 * (uv - u_tile.xy) / (u_tile.zw - u_tile.xy) - 1.0;
    // The highest surface wins the depth test (GL_LESS on 1 − height).
    float depth = 1.0 - 2.0 * clamp(a_height / u_max_height, 0.0, 1.0);
    gl_Position = vec4(ndc, depth, 1.0);
    v_height = a_height;
    v_fragment = int(a_fragment + 0.5) - 1;
    v_crack = a_crack;
    v_weight = a_weight;
    v_age = a_age;
}
