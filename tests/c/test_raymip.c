/* C11 test of the raymip C ABI (include/raymip.h, libraymip_ffi.a).
 * Expected values are computed here independently in double precision from
 * the formulas (log2 Pb = log2(texel width / pixel angle), lod = log2 Pl -
 * log2 Pb, ray-cone lod = log2 w - log2 |n.d|), not taken from the library.
 * Build and run: scripts/c-abi. Prints "N passed, M failed". */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "raymip.h"

static int passed, failed;

#define CHECK(cond, ...)                                                      \
    do {                                                                      \
        if (cond) {                                                           \
            passed++;                                                         \
        } else {                                                              \
            failed++;                                                         \
            fprintf(stderr, "%s:%d: FAIL %s: ", __FILE__, __LINE__, #cond);   \
            fprintf(stderr, __VA_ARGS__);                                     \
            fputc('\n', stderr);                                              \
        }                                                                     \
    } while (0)

static int64_t fx32(double x) { return (int64_t)llround(x * 4294967296.0); }
static double i16f16(int32_t b) { return b / 65536.0; }
static double i8f8(int16_t b) { return b / 256.0; }

static RmTriangle unit_triangle(double side, uint32_t tex) {
    RmTriangle t;
    memset(&t, 0, sizeof t);
    t.positions[1][0] = fx32(side);
    t.positions[2][1] = fx32(side);
    t.uvs[1][0] = fx32(1.0);
    t.uvs[2][1] = fx32(1.0);
    t.tex_width = tex;
    t.tex_height = tex;
    t.textured = 1;
    return t;
}

static void test_table_and_lod(void) {
    const int32_t spread = 1 << 20; /* I2F30: 2^-10 rad */
    const double gamma = ldexp(1.0, -10);
    RmTriangle tris[3] = {unit_triangle(1.0, 256), unit_triangle(4.0, 64), unit_triangle(1.0, 256)};
    tris[2].textured = 0;
    int32_t entries[3] = {0, 0, 0};
    RmBuildStats st;
    CHECK(rm_table_build(entries, 3, tris, 3, spread, &st) == RM_STATUS_OK, "build");
    CHECK(st.textured == 2 && st.untextured == 1, "stats %u %u", (unsigned)st.textured, (unsigned)st.untextured);
    /* Texel width sqrt(A/N): A = side^2/2, N = w*h/2 texels. */
    const double want0 = log2(sqrt(0.5 / (0.5 * 256.0 * 256.0)) / gamma);
    const double want1 = log2(sqrt(8.0 / (0.5 * 64.0 * 64.0)) / gamma);
    CHECK(fabs(i16f16(entries[0]) - want0) <= 1.0 / 1024, "entry0 %f want %f", i16f16(entries[0]), want0);
    CHECK(fabs(i16f16(entries[1]) - want1) <= 1.0 / 1024, "entry1 %f want %f", i16f16(entries[1]), want1);
    CHECK(entries[2] == RM_UNTEXTURED, "untextured marker %ld", (long)entries[2]);

    for (double pl = 0.01; pl < 5000.0; pl *= 1.7) {
        int16_t lod = 0;
        uint64_t plb = (uint64_t)llround(pl * 4294967296.0);
        CHECK(rm_table_lod(plb, entries[0], &lod) == RM_STATUS_OK, "lod status");
        double want = log2(pl) - want0;
        CHECK(fabs(i8f8(lod) - want) <= 1.0 / 256 + 1.0 / 1024, "lod %f want %f at Pl %f", i8f8(lod), want, pl);
    }
    int16_t lod = 77;
    CHECK(rm_table_lod(1ull << 32, entries[2], &lod) == RM_STATUS_UNTEXTURED && lod == 77, "untextured lod");
    CHECK(rm_table_lod(1ull << 32, entries[0], NULL) == RM_STATUS_NULL_POINTER, "null out");

    /* Update one entry; table full past the end. */
    RmTriangle big = unit_triangle(2.0, 256);
    CHECK(rm_table_update(entries, 3, 2, &big, 1, spread, NULL) == RM_STATUS_OK, "update");
    CHECK(fabs(i16f16(entries[2]) - (want0 + 1.0)) <= 1.0 / 1024, "updated entry %f", i16f16(entries[2]));
    RmTriangle two[2] = {big, big};
    CHECK(rm_table_update(entries, 3, 2, two, 2, spread, NULL) == RM_STATUS_TABLE_FULL, "table full");
    CHECK(rm_table_build(entries, 3, tris, 3, 0, NULL) == RM_STATUS_BAD_ANGLE, "bad angle");
    RmTriangle zero = unit_triangle(1.0, 0);
    CHECK(rm_table_build(entries, 3, &zero, 1, spread, NULL) == RM_STATUS_ZERO_SIZE, "zero texture");
    CHECK(rm_table_build(NULL, 3, tris, 3, spread, NULL) == RM_STATUS_NULL_POINTER, "null entries");

    /* Cone lod: log2 w + delta - log2 |n.d|. */
    CHECK(rm_cone_lod(fx32(1.0), 0, RM_COS_ONE) == 0, "cone w=1, no normal term");
    CHECK(rm_cone_lod(fx32(1.0), 0, 1u << 30) == 256, "cone n.d=0.5: %d", rm_cone_lod(fx32(1.0), 0, 1u << 30));
    CHECK(fabs(i8f8(rm_cone_lod(fx32(3.0), 2 << 16, RM_COS_ONE)) - (log2(3.0) + 2.0)) <= 1.0 / 256, "cone w=3");
    /* Grazing: |n.d| clamps at 2^-16 (as the Rust cone_lod), 16 levels coarser, never dropped. */
    CHECK(rm_cone_lod(fx32(1.0), 0, 0) == 16 * 256, "cone grazing n.d=0: %d", rm_cone_lod(fx32(1.0), 0, 0));
    CHECK(rm_cone_lod(fx32(1.0), 0, 1) == 16 * 256, "cone grazing n.d=2^-31: %d", rm_cone_lod(fx32(1.0), 0, 1));
    /* Delta = -log2 Pb - log2 gamma (gamma = 2^-10 rad: +10), the cone lod's triangle constant. */
    int32_t delta = 0;
    CHECK(rm_delta(entries[0], spread, &delta) == RM_STATUS_OK, "delta");
    CHECK(fabs(i16f16(delta) - (10.0 - i16f16(entries[0]))) <= 1.0 / 65536, "delta %f", i16f16(delta));
    delta = 7;
    CHECK(rm_delta(RM_UNTEXTURED, spread, &delta) == RM_STATUS_UNTEXTURED && delta == 7, "delta untextured");
    CHECK(rm_delta(entries[0], 0, &delta) == RM_STATUS_BAD_ANGLE && delta == 7, "delta bad angle");
    CHECK(rm_delta(entries[0], spread, NULL) == RM_STATUS_NULL_POINTER, "delta null out");
    CHECK(rm_clamp_lod(1000, 3) == 512 && rm_clamp_lod(-5, 3) == 0 && rm_clamp_lod(300, 3) == 300, "clamp");
}

static void test_ray_stack(void) {
    RmRayStack stack;
    RmPathState s, out;
    CHECK(rm_ray_stack_init(&stack) == RM_STATUS_OK && stack.len == 0, "init");
    CHECK(rm_path_primary(1 << 20, 0xA5, &s) == RM_STATUS_OK, "primary");
    CHECK(s.pl == 0 && s.cone_width == 0 && s.cone_spread == (1 << 20) && s.mask == 0xA5, "primary fields");
    CHECK(rm_path_advance(&s, 3ull << 31) == RM_STATUS_OK, "advance"); /* t = 1.5 */
    CHECK(s.pl == 3ull << 31, "pl %llu", (unsigned long long)s.pl);
    /* w = gamma * t = 2^-10 * 1.5, within 2^-32. */
    CHECK(llabs(s.cone_width - fx32(1.5 / 1024)) <= 1, "width %lld", (long long)s.cone_width);
    for (int i = 0; i < RM_RAY_STACK_CAPACITY; i++) {
        RmPathState b = s;
        CHECK(rm_path_bounce(&b, i) == RM_STATUS_OK && b.depth == 1, "bounce");
        CHECK(rm_ray_stack_push(&stack, &b) == RM_STATUS_OK, "push %d", i);
    }
    CHECK(rm_ray_stack_push(&stack, &s) == RM_STATUS_STACK_FULL && stack.len == RM_RAY_STACK_CAPACITY, "full");
    for (int i = RM_RAY_STACK_CAPACITY - 1; i >= 0; i--) {
        CHECK(rm_ray_stack_pop(&stack, &out) == RM_STATUS_OK, "pop");
        CHECK(out.cone_spread == (1 << 20) + i, "LIFO order: spread %ld", (long)out.cone_spread);
    }
    CHECK(rm_ray_stack_pop(&stack, &out) == RM_STATUS_STACK_EMPTY, "empty");
    CHECK(rm_ray_stack_push(NULL, &s) == RM_STATUS_NULL_POINTER, "null stack");
    /* Pushing an entry of the same stack (input aliases the stack). */
    CHECK(rm_ray_stack_push(&stack, &s) == RM_STATUS_OK, "push");
    CHECK(rm_ray_stack_push(&stack, &stack.entries[0]) == RM_STATUS_OK && stack.len == 2, "push own entry");
    CHECK(memcmp(&stack.entries[1], &s, sizeof s) == 0, "own entry copied");
    CHECK(rm_ray_stack_pop(&stack, &stack.entries[1]) == RM_STATUS_OK && stack.len == 1, "pop into own slot");
    CHECK(rm_ray_stack_pop(&stack, &out) == RM_STATUS_OK && stack.len == 0, "pop");
    /* A misaligned pointer is reported, never dereferenced. */
    _Alignas(8) unsigned char raw[sizeof(RmRayStack) + 8] = {0};
    CHECK(rm_ray_stack_init((RmRayStack *)(void *)(raw + 4)) == RM_STATUS_MISALIGNED, "misaligned stack");
    CHECK(rm_ray_stack_push(&stack, (const RmPathState *)(const void *)(raw + 4)) == RM_STATUS_MISALIGNED, "misaligned state");
    CHECK(rm_table_lod(1ull << 32, 0, (int16_t *)(void *)(raw + 1)) == RM_STATUS_MISALIGNED, "misaligned out");
    int untouched = 1;
    for (size_t i = 0; i < sizeof raw; i++) untouched &= raw[i] == 0;
    CHECK(untouched, "nothing written through a misaligned pointer");
    /* Saturation is flagged, never wraps. */
    RmPathState far = s;
    CHECK(rm_path_advance(&far, UINT64_MAX) == RM_STATUS_OK && far.saturated && far.pl == UINT64_MAX, "saturate");
}

static void test_sampling(void) {
    /* 4x4 texture with 3 levels; level 0 a 2x2-texel checker of two colours. */
    enum { W = 4, LEVELS = 3 };
    const uint32_t a = 0xFF204080u, b = 0xFF60C000u;
    size_t n = rm_pyramid_len(W, W, LEVELS);
    CHECK(n == 16 + 4 + 1, "pyramid len %zu", n);
    uint32_t texels[21] = {0};
    for (int y = 0; y < W; y++)
        for (int x = 0; x < W; x++) texels[y * W + x] = ((x / 2 + y / 2) % 2) ? b : a;
    /* Level 1 (2x2): each texel the box of one colour; level 2 the mean
     * (written out by hand here; rm_mip_generate must reproduce it). */
    texels[16] = a;
    texels[17] = b;
    texels[18] = b;
    texels[19] = a;
    texels[20] = 0;
    for (int c = 0; c < 4; c++) {
        uint32_t ca = (a >> (8 * c)) & 0xFF, cb = (b >> (8 * c)) & 0xFF;
        texels[20] |= ((ca + cb + 1) / 2) << (8 * c);
    }
    /* rm_mip_generate rebuilds levels 1.. from level 0 exactly as above. */
    uint32_t gen[21] = {0};
    memcpy(gen, texels, 16 * sizeof gen[0]);
    CHECK(rm_mip_generate(gen, n, W, W, LEVELS) == RM_STATUS_OK, "generate");
    CHECK(memcmp(gen, texels, sizeof gen) == 0, "generated levels differ: %08lx %08lx", (unsigned long)gen[16], (unsigned long)gen[20]);
    CHECK(rm_mip_generate(gen, n - 1, W, W, LEVELS) == RM_STATUS_BUFFER_TOO_SHORT, "generate short");
    CHECK(rm_mip_generate(NULL, n, W, W, LEVELS) == RM_STATUS_NULL_POINTER, "generate null");
    CHECK(rm_mip_generate(gen, n, 0, W, LEVELS) == RM_STATUS_ZERO_SIZE, "generate zero size");
    CHECK(rm_mip_generate(gen, n, W, W, 9) == RM_STATUS_OUT_OF_RANGE, "generate too many levels");
    RmTexture tex = {texels, n, W, W, LEVELS};
    /* One sampler per addressing, set up once and used for every sample. */
    RmSampler wrap, clamp;
    CHECK(rm_sampler_init(&wrap, &tex, RM_ADDRESS_WRAP) == RM_STATUS_OK, "init wrap");
    CHECK(rm_sampler_init(&clamp, &tex, RM_ADDRESS_CLAMP) == RM_STATUS_OK, "init clamp");
    uint32_t out = 0;
    /* Centre of texel (0,0) at level 0, every mode: colour a. */
    int64_t u = fx32(0.125), v = fx32(0.125);
    const RmMode modes[] = {RM_MODE_TRILINEAR, RM_MODE_BILINEAR_NEAREST_LEVEL, RM_MODE_NEAREST,
                            RM_MODE_NEAREST_TEXEL_LINEAR_LEVEL};
    for (int m = 0; m < 4; m++) {
        CHECK(rm_sample(&wrap, u, v, 0, modes[m], &out) == RM_STATUS_OK && out == a, "mode %d at level 0: %08lx", m, (unsigned long)out);
    }
    /* Coarsest level: the mean everywhere (lod clamped to 2). */
    CHECK(rm_sample(&clamp, fx32(0.3), fx32(0.9), 10 * 256, RM_MODE_TRILINEAR, &out) == RM_STATUS_OK && out == texels[20], "top %08lx", (unsigned long)out);
    /* Trilinear halfway between level 0 (a at this texel centre) and
     * level 1 (clamped addressing: u = 0.125 is below the first level-1
     * texel centre 0.25, so only that texel, a): a. */
    CHECK(rm_sample(&clamp, u, v, 128, RM_MODE_TRILINEAR, &out) == RM_STATUS_OK && out == a, "trilinear %08lx", (unsigned long)out);
    /* With wrapping, level 1 mixes in the wrapped neighbours (b): neither
     * pure colour. */
    CHECK(rm_sample(&wrap, u, v, 128, RM_MODE_TRILINEAR, &out) == RM_STATUS_OK && out != a && out != b, "trilinear wrap %08lx", (unsigned long)out);
    /* Bilinear on the edge between a and b at level 0: channel means. */
    rm_sample(&clamp, fx32(0.5), fx32(0.125), 0, RM_MODE_BILINEAR_NEAREST_LEVEL, &out);
    for (int c = 0; c < 4; c++) {
        int ca = (a >> (8 * c)) & 0xFF, cb = (b >> (8 * c)) & 0xFF;
        int got = (out >> (8 * c)) & 0xFF;
        CHECK(abs(got - (ca + cb) / 2) <= 1, "bilinear edge channel %d: %d", c, got);
    }
    /* A sampler set up once answers as one set up afresh for each sample
     * (the same texture, mode, lod and point), and a copy of it as well. */
    RmSampler copy = wrap;
    int same = 1;
    for (int i = 0; i < 64; i++) {
        int64_t su = fx32(i / 37.0 - 0.4), sv = fx32(i / 23.0 - 0.7);
        int16_t lod = (int16_t)(i * 53 - 300);
        RmSampler fresh;
        uint32_t once = 0, again = 0, copied = 0;
        same &= rm_sampler_init(&fresh, &tex, RM_ADDRESS_WRAP) == RM_STATUS_OK;
        same &= rm_sample(&wrap, su, sv, lod, modes[i % 4], &once) == RM_STATUS_OK;
        same &= rm_sample(&fresh, su, sv, lod, modes[i % 4], &again) == RM_STATUS_OK;
        same &= rm_sample(&copy, su, sv, lod, modes[i % 4], &copied) == RM_STATUS_OK;
        same &= once == again && once == copied;
    }
    CHECK(same, "a reused sampler differs from a fresh one");
    CHECK(rm_sample(&wrap, u, v, 0, (RmMode)9, &out) == RM_STATUS_OUT_OF_RANGE, "bad mode");
    RmSampler zeroed;
    memset(&zeroed, 0, sizeof zeroed);
    CHECK(rm_sample(&zeroed, u, v, 0, RM_MODE_NEAREST, &out) == RM_STATUS_UNINITIALISED, "zeroed sampler");
    RmSampler bad;
    CHECK(rm_sampler_init(&bad, &tex, (RmAddress)7) == RM_STATUS_OUT_OF_RANGE, "bad address");
    RmTexture short_tex = {texels, 5, W, W, LEVELS};
    CHECK(rm_sampler_init(&bad, &short_tex, RM_ADDRESS_WRAP) == RM_STATUS_BUFFER_TOO_SHORT, "short buffer");
    CHECK(rm_sampler_init(&bad, NULL, RM_ADDRESS_WRAP) == RM_STATUS_NULL_POINTER, "null texture");
    CHECK(rm_sample(NULL, u, v, 0, RM_MODE_NEAREST, &out) == RM_STATUS_NULL_POINTER, "null sampler");
    RmTexture bad_levels = {texels, n, W, W, 9};
    CHECK(rm_sampler_init(&bad, &bad_levels, RM_ADDRESS_WRAP) == RM_STATUS_OUT_OF_RANGE, "bad levels");
}

/* Exact bilinear (double) of channel c of a W x W wrapped level-0 RGBA8
 * texture at normalised (u, v): the reference of the filter bounds. */
static double bilinear_ref(const uint32_t *t, int w, double u, double v, int c) {
    double x = u * w - 0.5, y = v * w - 0.5;
    double x0 = floor(x), y0 = floor(y), fx = x - x0, fy = y - y0;
    double acc = 0.0;
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++) {
            int xi = (((int)x0 + i) % w + w) % w, yj = (((int)y0 + j) % w + w) % w;
            double wgt = (i ? fx : 1.0 - fx) * (j ? fy : 1.0 - fy);
            acc += wgt * ((t[yj * w + xi] >> (8 * c)) & 0xFF);
        }
    return acc;
}

static double channel_err(uint32_t got, const uint32_t *t, int w, double u, double v) {
    double worst = 0.0;
    for (int c = 0; c < 4; c++) {
        double e = fabs((double)((got >> (8 * c)) & 0xFF) - bilinear_ref(t, w, u, v, c));
        if (e > worst) worst = e;
    }
    return worst;
}

/* Sampler state through RmSamplerDesc (address per axis, border, bias,
 * clamps, FAST), images in other formats, batches and anisotropy. The
 * expected texels come from the addressing rules and formulas here. */
static void test_sampler_state(void) {
    enum { W = 8, N = 8 * 8 + 4 * 4 + 2 * 2 + 1 };
    uint32_t t[N];
    uint32_t x = 12345u;
    for (int i = 0; i < N; i++) {
        x = x * 1103515245u + 12345u;
        t[i] = x ^ (x >> 13);
    }
    RmTexture tex = {t, N, W, W, 4};
    RmSamplerDesc d;
    CHECK(rm_sampler_desc_default(&d) == RM_STATUS_OK, "desc default");
    CHECK(d.address_u == RM_ADDRESS_WRAP && d.precision == RM_PRECISION_ACCURATE && d.max_anisotropy == 1, "defaults");
    RmSampler s;
    uint32_t out = 0;
    const double h = 0.5 / W; /* half a texel */

    /* Border on both axes: outside [0, 1) the border colour, inside the texel. */
    d.address_u = RM_ADDRESS_BORDER;
    d.address_v = RM_ADDRESS_BORDER;
    d.border = 0x11223344u;
    CHECK(rm_sampler_init_desc(&s, &tex, &d) == RM_STATUS_OK, "init border");
    rm_sample(&s, fx32(-0.5), fx32(0.5), 0, RM_MODE_NEAREST, &out);
    CHECK(out == 0x11223344u, "border left %08lx", (unsigned long)out);
    rm_sample(&s, fx32(0.5), fx32(1.5), 0, RM_MODE_NEAREST, &out);
    CHECK(out == 0x11223344u, "border below %08lx", (unsigned long)out);
    rm_sample(&s, fx32(3 * 2 * h), fx32(5 * 2 * h), 0, RM_MODE_NEAREST, &out);
    CHECK(out == t[5 * W + 3], "border inside %08lx", (unsigned long)out);

    /* Mirror on u, clamp on v: u = -x reads texel of x, u in [1, 2) reads
     * 2 - u; v beyond the edge reads the last row. */
    d.address_u = RM_ADDRESS_MIRROR;
    d.address_v = RM_ADDRESS_CLAMP;
    CHECK(rm_sampler_init_desc(&s, &tex, &d) == RM_STATUS_OK, "init mirror/clamp");
    rm_sample(&s, fx32(-(2 * 2 * h + h)), fx32(1 * 2 * h + h), 0, RM_MODE_NEAREST, &out);
    CHECK(out == t[1 * W + 2], "mirror negative %08lx", (unsigned long)out);
    rm_sample(&s, fx32(1.0 + 2 * h + h), fx32(3.0), 0, RM_MODE_NEAREST, &out);
    CHECK(out == t[(W - 1) * W + (W - 2)], "mirror past 1, clamp v %08lx", (unsigned long)out);

    /* Bias +1 level: nearest at lod 0 reads level 1; max_lod 0 pins level 0. */
    CHECK(rm_sampler_desc_default(&d) == RM_STATUS_OK, "desc default");
    d.lod_bias = 256;
    CHECK(rm_sampler_init_desc(&s, &tex, &d) == RM_STATUS_OK, "init bias");
    rm_sample(&s, fx32(5 * 2 * h + h), fx32(2 * 2 * h + h), 0, RM_MODE_NEAREST, &out);
    CHECK(out == t[W * W + (2 / 2) * (W / 2) + 5 / 2], "bias +1 %08lx", (unsigned long)out);
    d.lod_bias = 0;
    d.max_lod = 0;
    CHECK(rm_sampler_init_desc(&s, &tex, &d) == RM_STATUS_OK, "init max lod");
    rm_sample(&s, fx32(5 * 2 * h + h), fx32(2 * 2 * h + h), 9 * 256, RM_MODE_NEAREST, &out);
    CHECK(out == t[2 * W + 5], "max lod 0 %08lx", (unsigned long)out);

    /* ACCURATE and FAST bilinear against the exact double filter on a
     * 1/1000-texel grid (between both tiers' sub-texel steps, so the
     * position rounding counts; the reference takes the fixed-point
     * coordinate exactly): ACCURATE <= 0.5625 LSB, FAST <= 1.5 LSB (the
     * bounds of the Rust docs). */
    RmSampler acc, fast;
    CHECK(rm_sampler_desc_default(&d) == RM_STATUS_OK, "desc default");
    CHECK(rm_sampler_init_desc(&acc, &tex, &d) == RM_STATUS_OK, "init accurate");
    d.precision = RM_PRECISION_FAST;
    CHECK(rm_sampler_init_desc(&fast, &tex, &d) == RM_STATUS_OK, "init fast");
    double worst_acc = 0.0, worst_fast = 0.0;
    for (int i = 0; i < 400; i++) {
        int64_t fu = fx32((double)((i * 377) % (1000 * W)) / (1000.0 * W));
        int64_t fv = fx32((double)((i * 911 + 7) % (1000 * W)) / (1000.0 * W));
        double u = (double)fu / 4294967296.0, v = (double)fv / 4294967296.0;
        uint32_t a = 0, f = 0;
        rm_sample(&acc, fu, fv, 0, RM_MODE_BILINEAR_NEAREST_LEVEL, &a);
        rm_sample(&fast, fu, fv, 0, RM_MODE_BILINEAR_NEAREST_LEVEL, &f);
        double ea = channel_err(a, t, W, u, v), ef = channel_err(f, t, W, u, v);
        if (ea > worst_acc) worst_acc = ea;
        if (ef > worst_fast) worst_fast = ef;
    }
    CHECK(worst_acc <= 0.5625, "ACCURATE bilinear error %f LSB", worst_acc);
    CHECK(worst_fast <= 1.5, "FAST bilinear error %f LSB", worst_fast);

    /* A batch gives the texels of single calls. */
    RmHit hits[40];
    uint32_t batch[40];
    for (int i = 0; i < 40; i++) {
        hits[i].u = fx32(i / 13.0 - 0.6);
        hits[i].v = fx32(i / 7.0 - 1.1);
        hits[i].lod = (int16_t)(i * 41 - 200);
    }
    CHECK(rm_sample_batch(&fast, hits, 40, RM_MODE_TRILINEAR, batch) == RM_STATUS_OK, "batch");
    int same = 1;
    for (int i = 0; i < 40; i++) {
        rm_sample(&fast, hits[i].u, hits[i].v, hits[i].lod, RM_MODE_TRILINEAR, &out);
        same &= out == batch[i];
    }
    CHECK(same, "batch differs from single calls");
    CHECK(rm_sample_batch(&fast, NULL, 0, RM_MODE_TRILINEAR, NULL) == RM_STATUS_OK, "empty batch");
    CHECK(rm_sample_batch(&fast, NULL, 3, RM_MODE_TRILINEAR, batch) == RM_STATUS_NULL_POINTER, "null batch");

    /* Anisotropic, 4x: a footprint 4 texels long in u, 1 in v gives four
     * level-0 bilinear probes at -1.5, -0.5, 0.5, 1.5 texels, averaged. */
    CHECK(rm_sampler_desc_default(&d) == RM_STATUS_OK, "desc default");
    d.max_anisotropy = 4;
    CHECK(rm_sampler_init_desc(&s, &tex, &d) == RM_STATUS_OK, "init aniso");
    RmFootprint fp = {fx32(4.0 / W), 0, 0, fx32(1.0 / W)};
    double worst_aniso = 0.0;
    for (int i = 0; i < 50; i++) {
        double u = (double)((i * 53) % (16 * W)) / (16.0 * W), v = (double)((i * 29 + 3) % (16 * W)) / (16.0 * W);
        CHECK(rm_sample_aniso(&s, fx32(u), fx32(v), &fp, &out) == RM_STATUS_OK, "aniso status");
        for (int c = 0; c < 4; c++) {
            double want = 0.0;
            for (int k = 0; k < 4; k++) want += bilinear_ref(t, W, u + (k - 1.5) / W, v, c) / 4.0;
            double e = fabs((double)((out >> (8 * c)) & 0xFF) - want);
            if (e > worst_aniso) worst_aniso = e;
        }
    }
    CHECK(worst_aniso <= 1.0, "aniso 4x error %f LSB", worst_aniso);
    CHECK(rm_sample_aniso(&s, 0, 0, NULL, &out) == RM_STATUS_NULL_POINTER, "aniso null footprint");

    /* An RGB565 image: nearest texels decode by bit replication, alpha 255. */
    uint8_t px[4 * 4 * 2 + 2 * 2 * 2 + 2];
    size_t len = rm_image_len(4, 4, 3, RM_FORMAT_RGB565);
    CHECK(len == sizeof px, "image len %zu", len);
    for (size_t i = 0; i < sizeof px; i++) px[i] = (uint8_t)(i * 37 + 11);
    RmImage img = {px, sizeof px, 4, 4, 3, RM_FORMAT_RGB565, 0};
    CHECK(rm_sampler_desc_default(&d) == RM_STATUS_OK, "desc default");
    CHECK(rm_sampler_init_image(&s, &img, &d) == RM_STATUS_OK, "init rgb565");
    same = 1;
    for (int y = 0; y < 4; y++)
        for (int xx = 0; xx < 4; xx++) {
            unsigned p = px[2 * (y * 4 + xx)] | (unsigned)px[2 * (y * 4 + xx) + 1] << 8;
            unsigned r = p >> 11, g = (p >> 5) & 63, b = p & 31;
            uint32_t want = ((r << 3) | (r >> 2)) | ((g << 2) | (g >> 4)) << 8 | ((b << 3) | (b >> 2)) << 16 | 0xFFu << 24;
            rm_sample(&s, fx32((xx + 0.5) / 4), fx32((y + 0.5) / 4), 0, RM_MODE_NEAREST, &out);
            same &= out == want;
        }
    CHECK(same, "rgb565 nearest texels");
    img.len = sizeof px - 1;
    CHECK(rm_sampler_init_image(&s, &img, &d) == RM_STATUS_BUFFER_TOO_SHORT, "short image");
    img.len = sizeof px;
    img.format = 99;
    CHECK(rm_sampler_init_image(&s, &img, &d) == RM_STATUS_OUT_OF_RANGE, "bad format");
    img.format = RM_FORMAT_A8;
    img.srgb = 1;
    CHECK(rm_sampler_init_image(&s, &img, &d) == RM_STATUS_OUT_OF_RANGE, "A8 has no sRGB variant");
    d.lod_bias = 16 * 256;
    CHECK(rm_sampler_init_desc(&s, &tex, &d) == RM_STATUS_OUT_OF_RANGE, "bias out of range");
    CHECK(rm_sampler_desc_default(&d) == RM_STATUS_OK, "desc default");
    d.max_anisotropy = 17;
    CHECK(rm_sampler_init_desc(&s, &tex, &d) == RM_STATUS_OUT_OF_RANGE, "anisotropy out of range");
}

/* Depth-first paths of RM_MAX_BOUNCES (10) bounces, each hit pushing two
 * continuations (a reflection and a refraction): every push succeeds,
 * 2^11 - 1 hits in all, and the stack is full at its deepest (one waiting
 * sibling per depth 1 .. 9, plus the two newest: 11 = (2 - 1) * 10 + 1,
 * worked out here by simulation, not taken from the header). */
static void test_deep_paths(void) {
    RmRayStack stack;
    RmPathState s;
    CHECK(rm_ray_stack_init(&stack) == RM_STATUS_OK, "init");
    CHECK(rm_path_primary(1 << 20, 0xFF, &s) == RM_STATUS_OK && rm_ray_stack_push(&stack, &s) == RM_STATUS_OK, "primary");
    long hits = 0, dropped = 0;
    unsigned most = stack.len, sim_len = 1, sim_most = 1;
    while (rm_ray_stack_pop(&stack, &s) == RM_STATUS_OK) {
        sim_len--;
        hits++;
        if (s.depth < 10) {
            for (int k = 0; k < 2; k++) {
                RmPathState c = s;
                rm_path_bounce(&c, 0);
                sim_len++;
                if (rm_ray_stack_push(&stack, &c) != RM_STATUS_OK) dropped++;
            }
        }
        most = stack.len > most ? stack.len : most;
        sim_most = sim_len > sim_most ? sim_len : sim_most;
    }
    CHECK(dropped == 0, "%ld continuations dropped", dropped);
    CHECK(hits == (1L << 11) - 1, "%ld hits", hits);
    CHECK(most == sim_most && most == RM_RAY_STACK_CAPACITY, "high water %u, simulated %u", most, sim_most);
    CHECK(RM_STACK_BOUND(10, 2) == 11 && RM_STACK_BOUND(7, 1) == 1 && RM_STACK_BOUND(4, 3) == 9, "RM_STACK_BOUND");
}

/* The fixed-point helpers of every format against the scaling by hand. */
static void test_helpers(void) {
    CHECK(RM_I32F32(0.75) == 3LL << 30 && RM_I32F32(-1.5) == -(3LL << 31), "I32F32");
    CHECK(RM_I32F32_INT(-3) == -(3LL << 32) && RM_I32F32_RATIO(3, 4) == 3LL << 30, "I32F32 int/ratio");
    CHECK(fabs(RM_I32F32_TO_DOUBLE(RM_I32F32(0.3)) - 0.3) < 1e-9, "I32F32 back");
    CHECK(RM_U32F32(100.5) == (100ULL << 32 | 1ULL << 31) && RM_U32F32_INT(147) == 147ULL << 32, "U32F32");
    CHECK(RM_U32F32_RATIO(1, 3) == 0x55555555ULL && RM_U32F32_TO_DOUBLE(RM_U32F32_INT(9)) == 9.0, "U32F32 ratio/back");
    CHECK(RM_I2F30(1.0 / 1024) == 1 << 20 && RM_I2F30_INT(1) == 1 << 30 && RM_I2F30_RATIO(-1, 1024) == -(1 << 20), "I2F30");
    CHECK(RM_I2F30_TO_DOUBLE(1 << 29) == 0.5, "I2F30 back");
    CHECK(RM_I16F16(-2.25) == -(9 << 14) && RM_I16F16_INT(-7) == -7 * 65536 && RM_I16F16_RATIO(1, 8) == 8192, "I16F16");
    CHECK(RM_I16F16_TO_DOUBLE(3 << 15) == 1.5, "I16F16 back");
    CHECK(RM_I8F8(1.62) == 415 && RM_I8F8_INT(-3) == -768 && RM_I8F8_RATIO(5, 2) == 640, "I8F8");
    CHECK(RM_I8F8_TO_DOUBLE(-384) == -1.5, "I8F8 back");
    CHECK(RM_U1F31(0.5) == 1u << 30 && RM_U1F31_INT(1) == RM_COS_ONE && RM_U1F31_RATIO(1, 4) == 1u << 29, "U1F31");
    CHECK(RM_U1F31_TO_DOUBLE(RM_COS_ONE) == 1.0, "U1F31 back");
}

int main(void) {
    test_table_and_lod();
    test_ray_stack();
    test_deep_paths();
    test_helpers();
    test_sampling();
    test_sampler_state();
    printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
