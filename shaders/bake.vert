// Orthographic projection of texture space: (u, v) → clip space, height → depth.
layout(location = 0) in vec2 a_uv;
layout(location = 1) in float a_height;
layout(location = 2) in vec3 a_normal;
layout(location = 3) in float a_fragment;
layout(location = 4) in float a_crack;

uniform vec4 u_tile;           // (u0, v0, u1, v1): the part of texture space this tile shows
uniform float u_max_height;    // m; maps height to depth
uniform vec2 u_offsets[9];     // periodic copies, one per instance

// Centroid interpolation: with multisampling a pixel whose centre lies outside a triangle that
// covers some of its samples would otherwise extrapolate the triangle's values to the centre;
// along steep crack walls that gave heights of -16..+20 mm on a 14 mm layer (needle spikes in
// the float displacement, inward normals).
centroid out vec2 v_uv;
centroid out float v_height;
centroid out vec3 v_normal;
flat out int v_fragment;
centroid out float v_crack;

void main()
{
    vec2 uv = a_uv + u_offsets[gl_InstanceID];
    vec2 ndc = 2.0 * (uv - u_tile.xy) / (u_tile.zw - u_tile.xy) - 1.0;
    // The highest surface wins the depth test (GL_LESS on 1 − height).
    float depth = 1.0 - 2.0 * clamp(a_height / u_max_height, 0.0, 1.0);
    gl_Position = vec4(ndc, depth, 1.0);
    v_uv = uv;
    v_height = a_height;
    v_normal = a_normal;
    v_fragment = int(a_fragment + 0.5) - 1;
    v_crack = a_crack;
}
