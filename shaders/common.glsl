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

// Value noise that tiles: a lattice of `cells` cells across the unit square whose corners
// wrap, smoothly interpolated. Integer cell counts make it periodic in u and v.
float crackle_value_noise(vec2 uv, ivec2 cells, uint seed)
{
    vec2 x = uv * vec2(cells);
    ivec2 i = ivec2(floor(x));
    vec2 f = fract(x);
    f = f * f * (3.0 - 2.0 * f);
    float v[4];
    for (int k = 0; k < 4; ++k) {
        ivec2 c = i + ivec2(k & 1, k >> 1);
        c = ((c % cells) + cells) % cells;
        v[k] = float(crackle_hash(uint(c.x) * 73856093u ^ uint(c.y) * 19349663u ^ crackle_hash(seed))) / 4294967296.0;
    }
    return mix(mix(v[0], v[1], f.x), mix(v[2], v[3], f.x), f.y);
}

// Four octaves of tiling value noise (fractal Brownian motion), in [0, 1].
float crackle_fbm(vec2 uv, ivec2 cells, uint seed)
{
    float sum = 0.0, amplitude = 0.5, total = 0.0;
    for (int o = 0; o < 4; ++o) {
        sum += amplitude * crackle_value_noise(uv, cells << o, seed + uint(o) * 1013u);
        total += amplitude;
        amplitude *= 0.5;
    }
    return sum / total;
}
