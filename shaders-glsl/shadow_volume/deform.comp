#version 460
// Shadow volumes on the GPU, before stage 1, for meshes an engine deforms on the GPU
// (`Shadows::add_deforming_mesh`, crates/umbra-shadows/src/shadow_volume/deform.rs): each
// welded position of the mesh copied from the engine's position stream, at the first of its
// vertices welded into it in the rest pose, so that stages 1 and 2 and the volume draws read
// this frame's pose. The bits are copied, never computed with: the volumes see exactly the
// positions the engine's own passes draw.
layout(local_size_x = 64) in;

// The engine's position stream, bound whole: 32-bit words.
layout(set = 0, binding = 0, std430) readonly buffer EnginePositions {
    uint engine_words[];
};

// Per welded position of every deforming mesh, the vertex it is read from (umbra_scene::Adjacency::welded_from).
layout(set = 0, binding = 1, std430) readonly buffer WeldedFrom {
    uint welded_from[];
};

// `volume_positions` of shadow_volume/gpu_volume.glsl, as bits.
layout(set = 0, binding = 2, std430) writeonly buffer VolumePositions {
    uvec4 volume_positions[];
};

layout(push_constant) uniform Push {
    uint first_word;      // the stream's byte offset / 4
    uint stride_words;    // its byte stride / 4
    uint first_position;  // the mesh's first welded position in volume_positions
    uint first_map;       // its first entry in welded_from
    uint count;           // its welded positions
} push;

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= push.count) {
        return;
    }
    uint w = push.first_word + welded_from[push.first_map + i] * push.stride_words;
    volume_positions[push.first_position + i] =
        uvec4(engine_words[w], engine_words[w + 1u], engine_words[w + 2u], floatBitsToUint(1.0));
}
