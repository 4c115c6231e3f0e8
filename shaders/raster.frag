#version 450 core
// Laser pass (render/raster_source.cpp): the nearest triangle along each
// column's ray wins the depth test (reversed float depth, early depth test),
// and its number (+1; 0 = no hit) is all that is written. The CPU then
// intersects the column's ray with that triangle's plane exactly, in double,
// so ranges match a ray caster to well under a micrometre.
layout(early_fragment_tests) in;

flat in uvec2 v_row_triangle;  // row in the pass, triangle (its hierarchy entry)

layout(location = 0) out uint o_triangle;

void main() {
  o_triangle = v_row_triangle.y + 1u;
}
