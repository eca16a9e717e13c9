// Ambient occlusion from the height field: for each texel, the horizon angle in a few
// directions within a radius (horizon-based AO over a height map, wrapping across the tile).
in vec2 v_uv;

uniform sampler2D u_height;   // metres, GL_REPEAT where the surface is periodic
uniform vec2 u_metres;        // metres per unit of u and v
uniform float u_radius;       // m
uniform float u_strength;

layout(location = 0) out vec4 o_ao;

void main()
{
    const int DIRECTIONS = 8;
    const int STEPS = 6;
    float h0 = texture(u_height, v_uv).r;
    float occlusion = 0.0;
    for (int d = 0; d < DIRECTIONS; ++d) {
        float angle = 6.28318530718 * (float(d) + 0.5) / float(DIRECTIONS);
        vec2 dir = vec2(cos(angle), sin(angle));
        float max_tan = 0.0;
        for (int s = 1; s <= STEPS; ++s) {
            float dist = u_radius * float(s) / float(STEPS);
            vec2 duv = dir * dist / u_metres;
            float h = texture(u_height, v_uv + duv).r;
            max_tan = max(max_tan, (h - h0) / dist);
        }
        occlusion += max_tan / sqrt(1.0 + max_tan * max_tan);  // sin of the horizon angle
    }
    float ao = 1.0 - u_strength * occlusion / float(DIRECTIONS);
    o_ao = vec4(clamp(ao, 0.0, 1.0), 0.0, 0.0, 1.0);
}
