// The trace interface (see trace/common.wgsl). This file is what a trace pass includes; the
// runtime substitutes the active back-end's module for it, so it holds the default: the
// `compute` back-end, which runs everywhere.
//#include "trace/compute.wgsl"
