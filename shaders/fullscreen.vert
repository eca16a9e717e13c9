// One triangle that covers the viewport; v_uv runs over the tile.
uniform vec4 u_tile;  // (u0, v0, u1, v1)
out vec2 v_uv;

void main()
{
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    v_uv = mix(u_tile.xy, u_tile.zw, p);
    gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
