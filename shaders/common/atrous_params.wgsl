// The parameters of layers/atrous.ron, shared by its passes (denoise/variance.wgsl,
// denoise/atrous.wgsl).
struct Params {
    sigma_luminance: f32,
    sigma_normal: f32,
    sigma_depth: f32,
    short_history: u32,
}

// `short_history`'s choices.
const SHORT_HISTORY_SPATIAL: u32 = 0u;
const SHORT_HISTORY_UNFILTERED: u32 = 1u;
