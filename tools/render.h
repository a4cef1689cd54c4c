/* render.h - a tiny software renderer for the examples and pvsview: flat-shaded triangles with a
   z-buffer into a plain RGBA8 array (top row first, 4 bytes per pixel: the layout png_write takes),
   through a pvs_camera (perspective or orthographic, pvs_camera_matrix's reversed depth: larger is
   nearer), near-plane clipping, alpha blending, an X-ray composite for hidden geometry, and a few 2D
   primitives (lines, rectangles) for plots and overlays. No dependency beyond libc/libm and pvs.h's
   camera matrix. Not part of the library. Thread-safe on distinct images. */
#ifndef TOOL_RENDER_H
#define TOOL_RENDER_H
#include "../pvs.h"
#include <stdint.h>

/* A colour as 0xRRGGBBAA (the same as TOOL_RGBA). */
#define RENDER_RGBA(r, g, b, a) (((uint32_t)(r) << 24) | ((uint32_t)(g) << 16) | ((uint32_t)(b) << 8) | (uint32_t)(a))

typedef struct render_image {
    uint32_t width, height;
    uint8_t *rgba;    /* width * height * 4, row 0 at the top */
    float *depth;     /* width * height, PVS_DEPTH_EMPTY where nothing was drawn; larger is nearer */
} render_image;

/* Allocates (malloc) a w x h image, cleared to black and empty depth. Returns 0 or -1. */
int render_image_init(render_image *im, uint32_t w, uint32_t h);
void render_image_free(render_image *im);
/* Fills the colour with rgba and the depth with PVS_DEPTH_EMPTY. */
void render_clear(render_image *im, uint32_t rgba);

/* A view: the camera's clip matrix for the image's aspect and the light for flat shading. */
typedef struct render_view {
    float m[16];         /* row-major, pvs_camera_matrix */
    float light[3];      /* unit vector toward the light */
    float ambient;       /* shade = ambient + (1 - ambient) |n . light|; 0 = 0.35 */
    float eye[3];        /* the camera's (RENDER_FRONT_ONLY) */
} render_view;

/* Sets up a view of `camera` for image im. Returns 0, or -1 for an unusable camera. */
int render_view_init(render_view *v, const pvs_camera *camera, const render_image *im);
/* A top-down orthographic camera over the ground rectangle (u0, v0)-(u1, v1) of a scene with up
   axis 1 (Y) or 2 (Z), looking down from above `top`; the ground axis u runs to the right, v
   downwards in the image. Fits the rectangle into an image of aspect w / h (the rest shows more). */
void render_top_camera(pvs_camera *camera, uint32_t up_axis, float u0, float v0, float u1, float v1, float top, uint32_t w, uint32_t h);
/* Projects a point: pixel coordinates (x right, y down, fractional) and its depth. Returns 0 when
   the point is behind the near plane. */
int render_project(const render_view *v, const render_image *im, const float p[3], float *x, float *y, float *depth);

/* Drawing flags. */
#define RENDER_NO_DEPTH_TEST 1u   /* draw over everything */
#define RENDER_NO_DEPTH_WRITE 2u  /* leave the z-buffer as it is */
#define RENDER_BLEND 4u           /* blend with the colour's alpha instead of overwriting */
#define RENDER_UNLIT 8u           /* the colour as is, no shading */
#define RENDER_FRONT_ONLY 16u     /* back faces left out, as an engine draws PVS_OBJECT_ONE_SIDED objects: a triangle
                                     whose normal (b - a) x (c - a) does not point toward the eye */

/* Draws `count` triangles (indices 3 each into positions, 3 floats per vertex; indices NULL =
   consecutive vertices) starting at triangle `first`, flat-shaded in `rgba`, two-sided (unless
   RENDER_FRONT_ONLY), clipped at the near plane, with the depth test "nearer or equal wins" unless
   flags say otherwise. Pixel (i, j) is drawn when its centre is inside the triangle. Returns the
   number of pixels written. */
uint64_t render_triangles(render_image *im, const render_view *v, const float *positions, const uint32_t *indices, uint32_t first,
                          uint32_t count, uint32_t rgba, unsigned flags);

/* X-ray composite: where `over` has something drawn, blend its colour over `im` with weight alpha
   (0..1). Both images have the same size. */
void render_composite(render_image *im, const render_image *over, float alpha);

/* 2D primitives in pixel coordinates (x right, y down), clipped to the image, alpha-blended when
   the colour's alpha is below 255. */
void render_pixel(render_image *im, int x, int y, uint32_t rgba);
void render_fill_rect(render_image *im, int x0, int y0, int x1, int y1, uint32_t rgba);   /* inclusive */
void render_rect(render_image *im, int x0, int y0, int x1, int y1, uint32_t rgba);        /* outline */
void render_line(render_image *im, float x0, float y0, float x1, float y1, uint32_t rgba, int width);

/* A heat-map colour for t in [0, 1]: dark blue, cyan, green, yellow, red. */
uint32_t render_heat(float t);

#endif
