#version 450 core
// The laser's depth map: the range (mm) of the nearest surface per direction.
in vec3 p_sensor;
layout(location = 0) out float range_mm;
void main() { range_mm = length(p_sensor); }
