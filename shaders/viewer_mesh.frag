#version 330 core
// vts-view: a headlight plus a fixed key light from above; two-sided, since
// neither profile source culls back faces and the viewer should not either.
in vec3 v_position_world;
in vec3 v_normal_world;

uniform vec3 u_eye_world;
uniform vec4 u_color;

out vec4 frag_color;

void main() {
  vec3 n = normalize(v_normal_world);
  vec3 to_eye = normalize(u_eye_world - v_position_world);
  if (dot(n, to_eye) < 0.0) n = -n;
  vec3 key = normalize(vec3(0.3, -0.4, 1.0));
  float head = max(dot(n, to_eye), 0.0);
  float diffuse = 0.55 * head + 0.25 * max(dot(n, key), 0.0);
  float spec = 0.25 * pow(max(dot(reflect(-to_eye, n), to_eye), 0.0), 24.0);
  frag_color = vec4(u_color.rgb * (0.22 + diffuse) + vec3(spec), u_color.a);
}
