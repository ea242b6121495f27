#version 460
// The resolve of primary visibility in compute (raster3d_resolve.frag.glsl): one triangle that
// covers the whole viewport, from gl_VertexIndex alone (no vertex input).
void main() {
  const vec2 p = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
