/* region.h -- private to the exdex core: integrals over a plane contact
 * region of uniform pressure, in closed form. Pure geometry: no model, no
 * allocation, every loop bounded (a polygon's edges; the disc's series at
 * most REGION_SERIES_MAX terms, its AGM REGION_AGM_MAX rounds). Used for the centre of pressure and e_r of
 * a region and by the exact limit surface (limitsurf.h).
 *
 * A region is a convex polygon (vertices counter-clockwise, 3 ..
 * REGION_MAX_VERTICES; collinear or repeated vertices are allowed, the area
 * must be positive) or a disc (centre, radius > 0), given in
 * any plane frame: every point argument below is in the same frame, and so
 * are the results (for a contact, the frame whose origin is the reference
 * point of the friction wrench).
 *
 * For a point c (anywhere: inside, on the boundary or outside), with
 * x = r - c over the region's points r and |x| its length:
 *   F(c)    = Int |x| dA                       [m^3]
 *   G(c)    = Int x / |x| dA                   [m^2]   (= -grad_c F)
 *   Phi(c)  = Int 1 / |x| dA                   [m]
 *   H(c)    = Int x x^T / |x|^3 dA             [m]     (2x2, symmetric,
 *             trace Phi; grad_c G = H - Phi I)
 * Polygons by the divergence and gradient theorems as sums over the edges
 * (div(x |x|) = 3 |x|, grad |x| = x / |x|, div(x / |x|) = 1 / |x| in the
 * plane), each edge integral of |x| and x/|x| in closed form with asinh;
 * discs by complete elliptic integrals K, E (from the boundary integral
 * over the circle; by the arithmetic-geometric mean, checked against GSL's
 * gsl_sf_ellint_Kcomp/_Ecomp), with a hypergeometric series for a centre
 * near the disc's centre or far from the disc (k^2 < 1/2) where the
 * Legendre combination cancels.
 *
 * Accuracy: to a few units of rounding relative to the integrals' scale
 * (A |c - centroid| + A rho, rho the region's largest vertex distance from
 * its centroid) for |c - centroid| up to a few rho; beyond that the sums
 * over edges cancel (their terms grow like |c|^2): the loss is about
 * (|c - centroid| / rho) units of rounding relative to F. Callers that need
 * the moment about a point far from c (a nearly translating slip) should
 * integrate the smooth integrand numerically there instead (limitsurf.c
 * does).
 */
#ifndef EXDEX_REGION_H
#define EXDEX_REGION_H

#define REGION_MAX_VERTICES 64
#define REGION_SERIES_MAX 80
#define REGION_AGM_MAX 40

enum region_kind {
    REGION_NONE = 0,     /* no region (a patch given by e_r alone) */
    REGION_POLYGON = 1,
    REGION_DISC = 2
};

typedef struct region {
    int kind;                           /* enum region_kind */
    int n;                              /* polygon: vertex count */
    double v[REGION_MAX_VERTICES][2];   /* polygon: vertices, counter-clockwise */
    double c[2];                        /* disc: centre */
    double r;                           /* disc: radius */
} region;

/* The integrals at one point c (see above). */
typedef struct region_moments {
    double dist;     /* F = Int |x| dA */
    double dir[2];   /* G = Int x / |x| dA */
    double inv;      /* Phi = Int 1 / |x| dA */
    double dyad[3];  /* H = Int x x^T / |x|^3 dA as (xx, xy, yy) */
} region_moments;

/* EXDEX_OK for a valid region: a polygon with 3 .. REGION_MAX_VERTICES
 * finite vertices, convex and counter-clockwise (every turn a left turn or
 * straight: every vertex on the left of or on every edge's line, to a
 * relative tolerance of 1e-12 of the squared size) with positive area and
 * a finite squared size; a disc with finite centre and finite radius > 0.
 * EXDEX_EINVAL otherwise (also for REGION_NONE). */
int region_check(const region *rg);

/* Fill a rectangle [cx - a, cx + a] x [cy - b, cy + b] (a, b > 0) or a disc. */
void region_set_rectangle(region *rg, double cx, double cy, double half_a, double half_b);
void region_set_disc(region *rg, double cx, double cy, double radius);

/* Area [m^2] and centroid of a valid region. */
double region_area(const region *rg);
void region_centroid(const region *rg, double g[2]);
/* Largest distance of a point of the region from the point c [m]. */
double region_reach(const region *rg, const double c[2]);

/* The integrals F, G, Phi and H of a valid region at c.
 * Returns EXDEX_OK, or EXDEX_EINVAL for a non-finite c. */
int region_moments_at(const region *rg, const double c[2], region_moments *out);

/* Mean distance of the region's points from c: F(c) / area [m]. With c the
 * centroid this is the ellipsoid's e_r of a uniform pressure region
 * (largest moment about the centroid per unit capacity). NaN for a
 * non-finite c. */
double region_mean_distance(const region *rg, const double c[2]);

#endif
