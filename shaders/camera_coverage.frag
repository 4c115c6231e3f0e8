#version 450 core
// Camera image (render/camera_renderer.cpp): which pixels see a surface.
// The ambient light a pixel records is the same on every surface
// (sensor/camera_image.h, ambient_radiance), so the renderer only needs
// this coverage, drawn without a depth test; the laser light is traced on
// the CPU (trace_laser_paths).
layout(location = 0) out float seen;
void main() { seen = 1.0; }
