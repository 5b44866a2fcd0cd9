// The subgroup operations (wgpu's SUBGROUP feature; WebGPU's `subgroups`), first in the pipelines
// that use them. wgpu's naga (30) takes them without WGSL's `enable subgroups;` (and refuses the
// directive); a browser's compiler needs it first in the text (`PipelineSource::browser_text`).
