#version 460
// The hardware rasterizer's ceilings (gpu/peaks.cpp): a regular grid of cellsX x cellsY cells, two
// triangles each, drawn indexed (vertices shared as in a mesh: about one vertex per two triangles),
// positions from gl_VertexIndex (no vertex input), depth only (no fragment shader, as the depth
// prepass). 2 x 2-pixel cells give the triangle rate of pixel-sized triangles, one cell the fill
// rate of two screen-sized ones (drawn once per instance).
layout(push_constant) uniform Push {
  uint cellsX, cellsY;
  uint pad0, pad1;
}
push;

void main() {
  const uint v = uint(gl_VertexIndex), x = v % (push.cellsX + 1u), y = v / (push.cellsX + 1u);
  const vec2 ndc = vec2(float(x) / float(push.cellsX), float(y) / float(push.cellsY)) * 2.0 - 1.0;
  gl_Position = vec4(ndc, 0.5 + 0.25 * float(gl_InstanceIndex % 2), 1.0);
}
