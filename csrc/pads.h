/* pads.h -- private to the exdex core: the contact region of a pad fixed on
 * a finger and the object's contact face, both convex, in the plate plane.
 *
 * A convex polygon is given by its vertices in counter-clockwise order
 * (pads_poly_ccw puts a clockwise one right). A disc enters the clipping as
 * the regular PADS_DISC_N-gon of the same area (pads_disc_poly), except
 * where one shape lies inside the other: a disc inside a polygon (or a
 * disc) is the region itself, exactly. Where a disc's rim crosses the other
 * shape the region is the clipped polygon: its boundary lies within
 * 3.3e-3 R of the rim (N = 32: the equal-area polygon's circumradius is
 * 1.0032 R, its apothem 0.9984 R), and its area, centroid and mean
 * distance err by that order (checked against a brute-force grid in the
 * test suite).
 *
 * Pure geometry: no model, no allocation, no output. */
#ifndef EXDEX_PADS_H
#define EXDEX_PADS_H

#include "exdex.h"

#define PADS_DISC_N 32
/* vertices of a region: a clip of an n-gon by a k-gon has at most n + k */
#define PADS_MAX_REGION (2 * PADS_DISC_N)

/* A convex shape of the plate plane: a polygon (n >= 3 vertices, ccw) or a
 * disc (n = 0, radius r > 0 about c). */
typedef struct pads_shape {
    int n;
    double v[PADS_MAX_REGION][2];
    double r, c[2];
} pads_shape;

/* The contact region and its integrals (uniform pressure). */
typedef struct pads_region {
    int n;                        /* polygon vertices (0 for an exact disc or an empty region) */
    double v[PADS_MAX_REGION][2];
    int disc;                     /* 1: the region is the disc (r, c) exactly */
    double r;
    double area;                  /* [m^2]; 0: empty */
    double c[2];                  /* centroid */
    double er;                    /* mean distance from the centroid, (1/A) Int |x - c| dA [m] */
} pads_region;

/* Twice the signed area of the polygon (positive for ccw). */
double pads_signed_area2(const double (*v)[2], int n);
/* 1 if the polygon is convex (strictly: every turn left once made ccw, no
 * repeated vertices), n >= 3 and finite; then reverses a clockwise one in
 * place so it is counter-clockwise. 0 otherwise (v unchanged). */
int pads_poly_ccw(double (*v)[2], int n);
/* The regular PADS_DISC_N-gon of the disc's area about c, its first vertex
 * at angle 0. */
void pads_disc_poly(const double c[2], double r, double (*out)[2]);
/* Sutherland-Hodgman: the convex polygon s (ns) clipped by the convex ccw
 * polygon k (nk), each of at most PADS_MAX_REGION vertices (else 0); out
 * holds up to PADS_MAX_REGION. Returns the count (< 3: empty). */
int pads_clip(const double (*s)[2], int ns, const double (*k)[2], int nk, double (*out)[2]);
/* Area, centroid and (1/A) Int |x - c| dA of a convex ccw polygon
 * (region.c's closed forms); area 0 for one region.c does not take. */
void pads_poly_props(const double (*v)[2], int n, double *area, double c[2], double *er);
/* The region a intersected with b (each a polygon or a disc). */
void pads_intersect(const pads_shape *a, const pads_shape *b, pads_region *out);

#endif
