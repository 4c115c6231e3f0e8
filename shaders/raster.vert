#version 450 core
// Laser pass, many profiles per draw (render/raster_source.cpp): the optical
// plane's slice of the mesh, rasterized into a target with one row per
// profile. The CPU cuts every triangle that crosses a profile's laser plane
// into its segment in that plane and sends the segment as one triangle inside
// the profile's row, already projected: its first end as an edge across the
// row, its second as the apex on the row's centre line, so along the row's
// pixel centres it covers exactly the segment's columns; x = NDC column
// coordinate (y/z over the fan's tangent), y = NDC y, z = near / z (reversed
// depth, exact along the segment because 1/z is affine in y/z on a line).
// Nothing is transformed or clipped here.
layout(location = 0) in vec3 a_ndc;
layout(location = 1) in uvec2 a_row_triangle;  // row in the pass, triangle (its hierarchy entry)

flat out uvec2 v_row_triangle;

void main() {
  gl_Position = vec4(a_ndc, 1.0);
  v_row_triangle = a_row_triangle;
}
