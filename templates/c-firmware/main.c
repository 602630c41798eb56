/* The per-hit flow of a texture-unit firmware in C, through the raymip C
 * ABI (include/raymip.h): set-up once (pixel spread from a fixed-point
 * angle, Pb table, a pyramid, sampler), then per hit path state -> lod ->
 * sample, with the two continuations of every hit on the ray stack, over
 * RM_MAX_BOUNCES bounces. The same flow and output as the Rust template
 * (templates/firmware/src/flow.rs); integer arithmetic only at run time.
 * Runs on the Cortex-M4 under QEMU (with startup.c and link.ld) and on
 * the host; the README gives both command lines. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#include "raymip.h"

/* Pixel spread atan(2 tan(fov/2) / rows) in radians: 60 degrees over 480
 * rows, worked out on the host (a constant: no float at run time). */
static const int32_t SPREAD = RM_I2F30(0.0024056);
/* Hit distances in scene units: the primary ray's and every later segment's. */
#define FIRST_T 20
#define NEXT_T 30
/* The texture: 64x64 texels, all 7 levels, each level one colour (RGBA8,
 * red in the low byte), so a sample's colour shows the levels it blended. */
#define SIZE 64
#define LEVELS 7
static const uint32_t LEVEL_RGBA[LEVELS] = {0xFF0000FF, 0xFF0080FF, 0xFF00FFFF, 0xFF00FF00,
                                            0xFFFFFF00, 0xFFFF0000, 0xFFFF00FF};
static uint32_t texels[5461]; /* rm_pyramid_len(64, 64, 7), checked below */

/* What the hits at one depth met: count, and the first one's lod and texel. */
static struct {
    long hits;
    int16_t lod;
    uint32_t rgba;
} depths[RM_MAX_BOUNCES + 1];

static const char *target(void) {
#if defined(__arm__)
    return "Cortex-M4F";
#else
    return "the host";
#endif
}

int main(void) {
    /* --- set-up (once per camera, scene and texture) --- */
    RmTriangle tri = {.positions = {{0, 0, 0}, {RM_I32F32_INT(1), 0, 0}, {0, RM_I32F32_INT(1), 0}},
                      .uvs = {{0, 0}, {RM_I32F32_INT(1), 0}, {0, RM_I32F32_INT(1)}},
                      .tex_width = SIZE, .tex_height = SIZE, .textured = 1};
    RmTriangle tris[2] = {tri, tri};
    int32_t entries[2];
    if (rm_table_build(entries, 2, tris, 2, SPREAD, NULL) != RM_STATUS_OK) return 1;
    if (rm_pyramid_len(SIZE, SIZE, LEVELS) != sizeof texels / sizeof texels[0]) return 1;
    for (size_t level = 0, i = 0; level < LEVELS; level++)
        for (size_t n = 0; n < (size_t)(SIZE >> level) * (SIZE >> level); n++) texels[i++] = LEVEL_RGBA[level];
    RmTexture tex = {.texels = texels, .len = sizeof texels / sizeof texels[0],
                     .width = SIZE, .height = SIZE, .levels = LEVELS};
    static RmSampler sampler;
    if (rm_sampler_init_wrap(&sampler, &tex) != RM_STATUS_OK) return 1;

    /* --- per hit: pop a path, trace its segment, lod, sample, push its continuations --- */
    RmRayStack stack;
    RmPathState path;
    rm_ray_stack_init(&stack);
    rm_path_primary(SPREAD, 0xFF, &path);
    rm_ray_stack_push(&stack, &path);
    unsigned most = 0;
    long dropped = 0;
    while (rm_ray_stack_pop(&stack, &path) == RM_STATUS_OK) {
        /* The accelerator traces the segment; here every ray hits triangle 1. */
        rm_path_advance(&path, RM_U32F32_INT(path.depth == 0 ? FIRST_T : NEXT_T));
        int16_t lod;
        if (rm_table_lod(path.pl, entries[1], &lod) != RM_STATUS_OK) continue; /* untextured */
        uint32_t rgba;
        rm_sample(&sampler, RM_I32F32_RATIO(3, 4), RM_I32F32_RATIO(1, 4), lod, RM_MODE_TRILINEAR, &rgba);
        if (depths[path.depth].hits++ == 0) {
            depths[path.depth].lod = lod;
            depths[path.depth].rgba = rgba;
        }
        if (path.depth < RM_MAX_BOUNCES) {
            for (int k = 0; k < 2; k++) { /* a flat mirror and a flat refractor: no spread */
                RmPathState next = path;
                rm_path_bounce(&next, 0);
                if (rm_ray_stack_push(&stack, &next) != RM_STATUS_OK) dropped++;
            }
        }
        most = stack.len > most ? stack.len : most;
    }

    printf("my-c-firmware on %s: %d bounces, two continuations per hit\n", target(), RM_MAX_BOUNCES);
    long hits = 0;
    for (int d = 0; d <= RM_MAX_BOUNCES; d++) {
        int hundredths = (abs(depths[d].lod) * 100 + 128) / 256;
        printf("depth %2d: %4ld hits, lod %s%d.%02d (bits %d), rgba 0x%08lx\n", d, depths[d].hits,
               depths[d].lod < 0 ? "-" : "", hundredths / 100, hundredths % 100, depths[d].lod,
               (unsigned long)depths[d].rgba);
        hits += depths[d].hits;
    }
    printf("ray stack: at most %u of %d entries, %ld continuations dropped; %ld hits\n", most,
           RM_RAY_STACK_CAPACITY, dropped, hits);
    return dropped == 0 ? 0 : 1;
}
