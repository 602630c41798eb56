/* Code-size probe of the C ABI: one configuration of calls per build
 * (scripts/c-abi builds each with -DRM_PROBE=<n> for the Cortex-M4 with
 * --gc-sections and subtracts the sections of RM_PROBE=0, the skeleton).
 * Inputs come through volatile reads, so nothing is folded away; the
 * images are measured, never run for their output.
 *   0  skeleton: start-up and exit, no raymip call
 *   1  the flow without a sampler: table lod and clamp, path state, ray stack
 *   2  1 + one RGBA8 wrap sampler (rm_sampler_init_wrap) and rm_sample
 *   3  1 + rm_sampler_init (address mode at run time) and rm_sample
 *   4  1 + rm_sampler_init_desc (every setting at run time) and rm_sample
 *   5  1 + rm_sampler_init_image (any format) and rm_sample
 *   6  every function of the header */
#include <stddef.h>
#include <stdint.h>

#include "raymip.h"

#ifndef RM_PROBE
#error "build with -DRM_PROBE=<n>"
#endif

static volatile int64_t in64[4];
static volatile int32_t in32[4];
static volatile uint32_t sink;
#if RM_PROBE >= 2
static uint32_t texels[85];
#endif

int main(void) {
    uint32_t acc = (uint32_t)in32[0];
#if RM_PROBE >= 1
    RmRayStack stack;
    RmPathState s;
    rm_ray_stack_init(&stack);
    rm_path_primary(in32[1], 0xFF, &s);
    rm_path_advance(&s, (uint64_t)in64[0]);
    rm_path_bounce(&s, in32[2]);
    rm_ray_stack_push(&stack, &s);
    rm_ray_stack_pop(&stack, &s);
    int16_t lod = 0;
    acc += (uint32_t)rm_table_lod(s.pl, in32[3], &lod);
    lod = rm_clamp_lod(lod, (uint8_t)in32[0]);
    acc += (uint16_t)lod;
#endif
#if RM_PROBE >= 2 && RM_PROBE <= 5
    static RmSampler sampler;
#if RM_PROBE <= 4
    RmTexture tex = {.texels = texels, .len = 85, .width = 8, .height = 8, .levels = (uint8_t)in32[1]};
#endif
#if RM_PROBE >= 4
    RmSamplerDesc desc;
    rm_sampler_desc_default(&desc);
    desc.address_u = (uint8_t)in32[2];
#endif
#if RM_PROBE == 2
    acc += (uint32_t)rm_sampler_init_wrap(&sampler, &tex);
#elif RM_PROBE == 3
    acc += (uint32_t)rm_sampler_init(&sampler, &tex, (uint8_t)in32[2]);
#elif RM_PROBE == 4
    acc += (uint32_t)rm_sampler_init_desc(&sampler, &tex, &desc);
#else
    RmImage img = {.bytes = (const uint8_t *)texels, .len = sizeof texels, .width = 8, .height = 8,
                   .levels = (uint8_t)in32[1], .format = (uint8_t)in32[3], .srgb = (uint8_t)in32[0]};
    acc += (uint32_t)rm_sampler_init_image(&sampler, &img, &desc);
#endif
    uint32_t texel = 0;
    acc += (uint32_t)rm_sample(&sampler, in64[1], in64[2], lod, (uint8_t)in32[3], &texel) + texel;
#endif
#if RM_PROBE == 6
    RmTriangle tri = {.tex_width = 8, .tex_height = 8, .textured = 1};
    int32_t entries[2];
    RmBuildStats stats;
    acc += (uint32_t)rm_table_build(entries, 2, &tri, 1, in32[1], &stats);
    acc += (uint32_t)rm_table_update(entries, 2, 1, &tri, 1, in32[1], NULL);
    int32_t delta = 0;
    acc += (uint32_t)rm_delta(entries[0], in32[1], &delta);
    acc += (uint32_t)rm_cone_lod(s.cone_width, delta, (uint32_t)in32[2]);
    acc += (uint32_t)rm_pyramid_len(8, 8, 4) + (uint32_t)rm_image_len(8, 8, 4, (uint8_t)in32[3]);
    acc += (uint32_t)rm_mip_generate(texels, 85, 8, 8, (uint8_t)in32[1]);
    static RmSampler a, b, c, d;
    RmTexture tex = {.texels = texels, .len = 85, .width = 8, .height = 8, .levels = 4};
    RmSamplerDesc desc;
    rm_sampler_desc_default(&desc);
    RmImage img = {.bytes = (const uint8_t *)texels, .len = sizeof texels, .width = 8, .height = 8,
                   .levels = 4, .format = (uint8_t)in32[3]};
    acc += (uint32_t)rm_sampler_init_wrap(&a, &tex) + (uint32_t)rm_sampler_init(&b, &tex, (uint8_t)in32[2]);
    acc += (uint32_t)rm_sampler_init_desc(&c, &tex, &desc) + (uint32_t)rm_sampler_init_image(&d, &img, &desc);
    RmHit hits[2] = {{in64[1], in64[2], lod}, {in64[2], in64[1], lod}};
    uint32_t out[2];
    acc += (uint32_t)rm_sample(&a, in64[1], in64[2], lod, (uint8_t)in32[3], out);
    acc += (uint32_t)rm_sample_batch(&c, hits, 2, (uint8_t)in32[3], out);
    RmFootprint fp = {in64[0], in64[1], in64[2], in64[3]};
    acc += (uint32_t)rm_sample_aniso(&d, in64[1], in64[2], &fp, out) + out[0] + out[1];
#endif
    sink = acc;
    return 0;
}
