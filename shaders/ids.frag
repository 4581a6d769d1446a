#version 450
layout(location = 0) flat in uint triangle_id;
layout(location = 0) out uint id;

void main() { id = triangle_id; }
