// A flat colour per piece, black on the crack floor (the _ID map; no anti-aliasing).
flat in int v_fragment;
centroid in vec2 v_uv;
centroid in float v_height;
centroid in vec3 v_normal;
centroid in float v_crack;

uniform uint u_seed;

layout(location = 0) out vec4 o_id;

void main()
{
    if (v_fragment < 0) {
        o_id = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    o_id = vec4(crackle_random(v_fragment, 10u, u_seed), crackle_random(v_fragment, 11u, u_seed),
                crackle_random(v_fragment, 12u, u_seed), 1.0) * 0.8 + 0.2;
}
