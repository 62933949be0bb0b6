#version 460
// Volume overdraw (Chan–Durand Fig. 3, 10a): every volume fragment adds 1/255 to red, with
// additive blending and no depth test, so the red channel counts rasterized volume fragments.
layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(1.0 / 255.0, 0.0, 0.0, 0.0);
}
