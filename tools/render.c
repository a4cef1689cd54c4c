/* render.c - see render.h */
#include "render.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

int render_image_init(render_image *im, uint32_t w, uint32_t h) {
    memset(im, 0, sizeof(*im));
    if (!w || !h || w > 16384 || h > 16384) return -1;
    im->rgba = (uint8_t *)malloc((size_t)w * h * 4);
    im->depth = (float *)malloc((size_t)w * h * sizeof(float));
    if (!im->rgba || !im->depth) {
        render_image_free(im);
        return -1;
    }
    im->width = w;
    im->height = h;
    render_clear(im, RENDER_RGBA(0, 0, 0, 255));
    return 0;
}

void render_image_free(render_image *im) {
    free(im->rgba);
    free(im->depth);
    memset(im, 0, sizeof(*im));
}

void render_clear(render_image *im, uint32_t c) {
    size_t i, n = (size_t)im->width * im->height;
    for (i = 0; i < n; ++i) {
        im->rgba[4 * i + 0] = (uint8_t)(c >> 24);
        im->rgba[4 * i + 1] = (uint8_t)(c >> 16);
        im->rgba[4 * i + 2] = (uint8_t)(c >> 8);
        im->rgba[4 * i + 3] = (uint8_t)c;
        im->depth[i] = PVS_DEPTH_EMPTY;
    }
}

int render_view_init(render_view *v, const pvs_camera *camera, const render_image *im) {
    float l = sqrtf(0.3f * 0.3f + 1.0f + 0.5f * 0.5f);
    memset(v, 0, sizeof(*v));
    if (pvs_camera_matrix(camera, (float)im->width / (float)im->height, v->m) != PVS_OK) return -1;
    /* a light from above and to the side, so walls facing different ways get different shades */
    v->light[0] = 0.3f / l;
    v->light[1] = 1.0f / l;
    v->light[2] = 0.5f / l;
    v->ambient = 0.35f;
    memcpy(v->eye, camera->eye, sizeof(v->eye));
    return 0;
}

void render_top_camera(pvs_camera *c, uint32_t up_axis, float u0, float v0, float u1, float v1, float top, uint32_t w, uint32_t h) {
    float eu = u1 - u0, ev = v1 - v0, aspect = (float)w / (float)h, cu = 0.5f * (u0 + u1), cv = 0.5f * (v0 + v1);
    memset(c, 0, sizeof(*c));
    c->fov_y = 0.0f;
    c->ortho_height = ev > eu / aspect ? ev : eu / aspect;
    if (!(c->ortho_height > 0.0f)) c->ortho_height = 1.0f;
    c->near_plane = 0.5f;
    c->far_plane = top + 2000.0f;
    if (up_axis == 2) {
        c->eye[0] = cu; c->eye[1] = cv; c->eye[2] = top + 1.0f;
        c->forward[2] = -1.0f;
        c->up[1] = 1.0f;
    } else {
        c->eye[0] = cu; c->eye[1] = top + 1.0f; c->eye[2] = cv;
        c->forward[1] = -1.0f;
        c->up[2] = -1.0f;
    }
}

/* clip = m * (p, 1) */
static void xform(const float *m, const float p[3], double out[4]) {
    int r;
    for (r = 0; r < 4; ++r) out[r] = (double)m[4 * r] * p[0] + (double)m[4 * r + 1] * p[1] + (double)m[4 * r + 2] * p[2] + m[4 * r + 3];
}

int render_project(const render_view *v, const render_image *im, const float p[3], float *x, float *y, float *depth) {
    double c[4];
    xform(v->m, p, c);
    if (!(c[3] > 0.0) || c[2] > c[3]) return 0;
    *x = (float)((c[0] / c[3] + 1.0) * 0.5 * im->width);
    *y = (float)((1.0 - c[1] / c[3]) * 0.5 * im->height);
    if (depth) *depth = (float)(c[2] / c[3]);
    return 1;
}

static void put_blend(uint8_t *px, uint32_t c, unsigned flags) {
    uint32_t a = c & 255u;
    if (!(flags & RENDER_BLEND) || a >= 255u) {
        px[0] = (uint8_t)(c >> 24); px[1] = (uint8_t)(c >> 16); px[2] = (uint8_t)(c >> 8); px[3] = 255;
        return;
    }
    px[0] = (uint8_t)((px[0] * (255u - a) + ((c >> 24) & 255u) * a + 127u) / 255u);
    px[1] = (uint8_t)((px[1] * (255u - a) + ((c >> 16) & 255u) * a + 127u) / 255u);
    px[2] = (uint8_t)((px[2] * (255u - a) + ((c >> 8) & 255u) * a + 127u) / 255u);
    px[3] = 255;
}

/* One screen-space triangle (x, y in pixels, z = depth). */
static uint64_t raster(render_image *im, const double *p0, const double *p1, const double *p2, uint32_t c, unsigned flags) {
    double minx = p0[0], maxx = p0[0], miny = p0[1], maxy = p0[1], area, z0, dzx, dzy;
    int x0, x1, y0, y1, x, y;
    uint64_t written = 0;
    minx = p1[0] < minx ? p1[0] : minx; maxx = p1[0] > maxx ? p1[0] : maxx;
    minx = p2[0] < minx ? p2[0] : minx; maxx = p2[0] > maxx ? p2[0] : maxx;
    miny = p1[1] < miny ? p1[1] : miny; maxy = p1[1] > maxy ? p1[1] : maxy;
    miny = p2[1] < miny ? p2[1] : miny; maxy = p2[1] > maxy ? p2[1] : maxy;
    if (maxx < 0.0 || maxy < 0.0 || minx > im->width || miny > im->height) return 0;
    area = (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p1[1] - p0[1]) * (p2[0] - p0[0]);
    if (!(fabs(area) > 1e-12)) return 0;
    /* depth as a plane over the screen: z = z0 + dzx (x - p0x) + dzy (y - p0y) */
    dzx = ((p1[2] - p0[2]) * (p2[1] - p0[1]) - (p2[2] - p0[2]) * (p1[1] - p0[1])) / area;
    dzy = ((p2[2] - p0[2]) * (p1[0] - p0[0]) - (p1[2] - p0[2]) * (p2[0] - p0[0])) / area;
    z0 = p0[2];
    x0 = minx < 0.0 ? 0 : (int)floor(minx);
    y0 = miny < 0.0 ? 0 : (int)floor(miny);
    x1 = maxx >= im->width ? (int)im->width - 1 : (int)floor(maxx);
    y1 = maxy >= im->height ? (int)im->height - 1 : (int)floor(maxy);
    for (y = y0; y <= y1; ++y) {
        double py = y + 0.5;
        for (x = x0; x <= x1; ++x) {
            double px = x + 0.5, w0, w1, w2, z;
            size_t i;
            w0 = (p1[0] - px) * (p2[1] - py) - (p1[1] - py) * (p2[0] - px);
            w1 = (p2[0] - px) * (p0[1] - py) - (p2[1] - py) * (p0[0] - px);
            w2 = (p0[0] - px) * (p1[1] - py) - (p0[1] - py) * (p1[0] - px);
            if (area > 0.0 ? (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) : (w0 > 0.0 || w1 > 0.0 || w2 > 0.0)) continue;
            z = z0 + dzx * (px - p0[0]) + dzy * (py - p0[1]);
            i = (size_t)y * im->width + (size_t)x;
            if (!(flags & RENDER_NO_DEPTH_TEST) && z < im->depth[i]) continue;
            if (!(flags & RENDER_NO_DEPTH_WRITE)) im->depth[i] = (float)z;
            put_blend(im->rgba + 4 * i, c, flags);
            ++written;
        }
    }
    return written;
}

uint64_t render_triangles(render_image *im, const render_view *v, const float *positions, const uint32_t *indices, uint32_t first,
                          uint32_t count, uint32_t rgba, unsigned flags) {
    uint32_t t;
    uint64_t written = 0;
    for (t = first; t < first + count; ++t) {
        const float *p[3];
        double c[3][4], poly[4][4], scr[4][3], d[3], n[3], e1[3], e2[3], len, shade = 1.0;
        uint32_t col = rgba;
        int k, np = 0;
        for (k = 0; k < 3; ++k) {
            p[k] = positions + 3 * (size_t)(indices ? indices[3 * (size_t)t + (uint32_t)k] : 3 * t + (uint32_t)k);
            xform(v->m, p[k], c[k]);
            d[k] = c[k][3] - c[k][2]; /* >= 0 in front of the near plane */
        }
        if (d[0] < 0.0 && d[1] < 0.0 && d[2] < 0.0) continue;
        for (k = 0; k < 3; ++k) {
            e1[k] = (double)p[1][k] - p[0][k];
            e2[k] = (double)p[2][k] - p[0][k];
        }
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        if ((flags & RENDER_FRONT_ONLY) && !(n[0] * ((double)v->eye[0] - p[0][0]) + n[1] * ((double)v->eye[1] - p[0][1]) +
                                            n[2] * ((double)v->eye[2] - p[0][2]) > 0.0))
            continue; /* faces away from the eye */
        if (!(flags & RENDER_UNLIT)) {
            double ldot;
            len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
            if (!(len > 0.0)) continue;
            ldot = fabs((n[0] * v->light[0] + n[1] * v->light[1] + n[2] * v->light[2]) / len);
            shade = v->ambient + (1.0 - v->ambient) * ldot;
            col = ((uint32_t)((double)((rgba >> 24) & 255u) * shade) << 24) | ((uint32_t)((double)((rgba >> 16) & 255u) * shade) << 16) |
                  ((uint32_t)((double)((rgba >> 8) & 255u) * shade) << 8) | (rgba & 255u);
        }
        /* clip the triangle to d >= 0 (Sutherland-Hodgman, one plane): at most 4 vertices */
        for (k = 0; k < 3; ++k) {
            int j = (k + 1) % 3, m;
            if (d[k] >= 0.0) { for (m = 0; m < 4; ++m) poly[np][m] = c[k][m]; ++np; }
            if ((d[k] >= 0.0) != (d[j] >= 0.0)) {
                double s = d[k] / (d[k] - d[j]);
                for (m = 0; m < 4; ++m) poly[np][m] = c[k][m] + s * (c[j][m] - c[k][m]);
                ++np;
            }
        }
        for (k = 0; k < np; ++k) {
            double w = poly[k][3] > 1e-9 ? poly[k][3] : 1e-9;
            scr[k][0] = (poly[k][0] / w + 1.0) * 0.5 * im->width;
            scr[k][1] = (1.0 - poly[k][1] / w) * 0.5 * im->height;
            scr[k][2] = poly[k][2] / w;
        }
        if (np >= 3) written += raster(im, scr[0], scr[1], scr[2], col, flags);
        if (np == 4) written += raster(im, scr[0], scr[2], scr[3], col, flags);
    }
    return written;
}

void render_composite(render_image *im, const render_image *over, float alpha) {
    size_t i, n = (size_t)im->width * im->height;
    uint32_t a = (uint32_t)(alpha * 255.0f + 0.5f);
    if (over->width != im->width || over->height != im->height) return;
    for (i = 0; i < n; ++i) {
        const uint8_t *s = over->rgba + 4 * i;
        if (over->depth[i] == PVS_DEPTH_EMPTY) continue;
        put_blend(im->rgba + 4 * i, ((uint32_t)s[0] << 24) | ((uint32_t)s[1] << 16) | ((uint32_t)s[2] << 8) | (a > 255u ? 255u : a),
                  RENDER_BLEND);
    }
}

void render_pixel(render_image *im, int x, int y, uint32_t c) {
    if (x < 0 || y < 0 || x >= (int)im->width || y >= (int)im->height) return;
    put_blend(im->rgba + 4 * ((size_t)y * im->width + (size_t)x), c, RENDER_BLEND);
}

void render_fill_rect(render_image *im, int x0, int y0, int x1, int y1, uint32_t c) {
    int x, y;
    if (x0 > x1) { x = x0; x0 = x1; x1 = x; }
    if (y0 > y1) { y = y0; y0 = y1; y1 = y; }
    if (x0 < 0) x0 = 0;
    if (y0 < 0) y0 = 0;
    if (x1 >= (int)im->width) x1 = (int)im->width - 1;
    if (y1 >= (int)im->height) y1 = (int)im->height - 1;
    for (y = y0; y <= y1; ++y)
        for (x = x0; x <= x1; ++x) put_blend(im->rgba + 4 * ((size_t)y * im->width + (size_t)x), c, RENDER_BLEND);
}

void render_rect(render_image *im, int x0, int y0, int x1, int y1, uint32_t c) {
    render_fill_rect(im, x0, y0, x1, y0, c);
    render_fill_rect(im, x0, y1, x1, y1, c);
    if (y1 - y0 > 1 || y0 - y1 > 1) {
        int lo = y0 < y1 ? y0 + 1 : y1 + 1, hi = y0 < y1 ? y1 - 1 : y0 - 1;
        render_fill_rect(im, x0, lo, x0, hi, c);
        render_fill_rect(im, x1, lo, x1, hi, c);
    }
}

void render_line(render_image *im, float x0, float y0, float x1, float y1, uint32_t c, int width) {
    double dx = (double)x1 - x0, dy = (double)y1 - y0, len = fabs(dx) > fabs(dy) ? fabs(dx) : fabs(dy);
    int k, n, h = width > 1 ? width / 2 : 0;
    if (!(len < 1e6)) return; /* also NaN */
    n = (int)ceil(len);
    for (k = 0; k <= n; ++k) {
        double t = n ? (double)k / n : 0.0;
        int x = (int)floor(x0 + dx * t), y = (int)floor(y0 + dy * t), a, b;
        if (width <= 1) {
            render_pixel(im, x, y, c);
            continue;
        }
        for (b = -h; b < width - h; ++b)
            for (a = -h; a < width - h; ++a) render_pixel(im, x + a, y + b, c);
    }
}

uint32_t render_heat(float t) {
    static const float stops[5][3] = {{20, 40, 140}, {0, 170, 220}, {40, 200, 60}, {250, 220, 30}, {220, 30, 30}};
    float f;
    int i;
    if (!(t > 0.0f)) t = 0.0f;
    if (t > 1.0f) t = 1.0f;
    f = t * 4.0f;
    i = (int)f;
    if (i > 3) i = 3;
    f -= (float)i;
    return RENDER_RGBA(stops[i][0] + (stops[i + 1][0] - stops[i][0]) * f, stops[i][1] + (stops[i + 1][1] - stops[i][1]) * f,
                       stops[i][2] + (stops[i + 1][2] - stops[i][2]) * f, 255);
}
