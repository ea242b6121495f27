#version 460
// The hardware rasterizer's ceilings (gpu/peaks.cpp): triangles generated from gl_VertexIndex,
// no vertex input, depth only (no fragment shader, as the depth prepass). The target is split
// into cellsX x cellsY cells of two triangles each: 1 x 1-pixel cells give the triangle rate of
// pixel-sized triangles, one cell the fill rate of two screen-sized ones (drawn once per instance).
layout(push_constant) uniform Push {
  uint cellsX, cellsY;
  uint pad0, pad1;
}
push;

void main() {
  const uint tri = uint(gl_VertexIndex) / 3u, corner = uint(gl_VertexIndex) % 3u;
  const uint cell = tri / 2u, upper = tri % 2u;
  const uint cx = cell % push.cellsX, cy = cell / push.cellsX;
  // Corners of the cell's two triangles: (0,0) (1,0) (0,1) and (1,0) (1,1) (0,1).
  const uvec2 lower[3] = uvec2[3](uvec2(0, 0), uvec2(1, 0), uvec2(0, 1));
  const uvec2 upperC[3] = uvec2[3](uvec2(1, 0), uvec2(1, 1), uvec2(0, 1));
  const uvec2 c = upper == 1u ? upperC[corner] : lower[corner];
  const vec2 ndc = vec2(float(cx + c.x) / float(push.cellsX), float(cy + c.y) / float(push.cellsY)) * 2.0 - 1.0;
  gl_Position = vec4(ndc, 0.5 + 0.25 * float(gl_InstanceIndex % 2), 1.0);
}
