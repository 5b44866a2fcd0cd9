// The generated grass's visible lists as the draws read them (generated.wgsl `listed`, which
// fills them): the instanced grass's four levels, then the billboards; a blade's 32 bytes as two
// words of four.

@group(0) @binding(12) var<storage, read> listed: array<vec4<u32>>;
