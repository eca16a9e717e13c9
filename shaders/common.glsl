// Shared helpers, pasted after the #version line of every shader (render/gl_program.cpp).
// The same hash as render/noise.hpp's hash32, so the CPU and GPU agree on a piece's numbers.

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
