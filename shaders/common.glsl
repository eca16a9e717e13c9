// Shared helpers, pasted after the #version line of every shader (render/gl_program.cpp).

// Integer hash (Wang / splitmix style), deterministic on every GL implementation.
uint crackle_hash(uint x)
{
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    x ^= x >> 16u;
    return x;
}

// Uniform in [0, 1) from a piece label and a channel.
float crackle_random(int label, uint channel, uint seed)
{
    return float(crackle_hash(uint(label) * 0x9e3779b9u ^ crackle_hash(channel + seed * 0x85ebca6bu))) / 4294967296.0;
}

// Smooth noise that tiles with period 1 in u and v: a few integer-frequency cosines.
float crackle_tiling_noise(vec2 uv, uint seed)
{
    const float TAU = 6.28318530718;
    float s = 0.0;
    for (int i = 0; i < 6; ++i) {
        float fi = float(i);
        vec2 k = vec2(float(int(crackle_hash(seed + uint(i)) % 23u) + 3), float(int(crackle_hash(seed + uint(i) + 77u) % 23u) + 3));
        float phase = TAU * float(crackle_hash(seed + uint(i) * 13u + 5u) % 1000u) / 1000.0;
        s += cos(TAU * dot(k * (1.0 + step(3.0, fi)), uv) + phase) / (1.0 + fi);
    }
    return 0.5 + 0.25 * s;
}
