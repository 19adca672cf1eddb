// The mesh's vertices (SurfaceVertex per vertex), which emit_mesh.comp writes and the renderer draws from.
layout(std430, binding = FIRN_BINDING_SURFACE_VERTICES) buffer SurfaceVertexBuffer { SurfaceVertex vertices[]; };
