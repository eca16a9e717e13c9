// One piece per texel (no anti-aliasing): the _ID map's colour (black on the crack floor) and
// the layers the CPU passes shape the maps from.
flat in int v_fragment;
centroid in float v_height;
centroid in float v_crack;
centroid in float v_weight;
centroid in float v_age;

uniform uint u_seed;

layout(location = 0) out vec4 o_id;     // rgb: a colour per piece
layout(location = 1) out vec4 o_layers; // r: piece label (−1 floor), g: crack, b: crack weight, a: crack age

void main()
{
    bool crack = v_crack > 0.5;
    // g: 0 plate, 1 crack wall or floor, 2 a lip line
    o_layers = vec4(float(v_fragment), v_crack > 1.5 ? 2.0 : (crack ? 1.0 : 0.0), v_weight, v_age);
    if (v_fragment < 0) {
        o_id = vec4(0.0, 0.0, 0.0, 1.0);
        return;
    }
    o_id = vec4(crackle_random(v_fragment, 10u, u_seed), crackle_random(v_fragment, 11u, u_seed),
                crackle_random(v_fragment, 12u, u_seed), 1.0) * 0.8 + 0.2;
}
