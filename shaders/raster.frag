#version 450 core
// Writes the primitive id: the object's first id plus the triangle index within the draw
// (0 is reserved for the background; see PrimitiveIdTable).
layout(location = 11) uniform uint uFirstId;
layout(location = 0) out uint outPrimitiveId;

void main() { outPrimitiveId = uFirstId + uint(gl_PrimitiveID); }
