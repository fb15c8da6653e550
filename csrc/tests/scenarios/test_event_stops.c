/* test_event_stops.c -- the event method on planar scenes whose stop events
 * are delicate (scenes of the Python scene zoo, tests/zoo.py, written out
 * here with every parameter): a contact-set row separating where its force
 * and gap acceleration both vanish (the complementarity solve at the decided
 * state can return a force of rounding size for it), a corner lifted off by
 * an impact coming back down within the next step (its gap is 0 to rounding
 * at the step start, a zero that is no crossing), a box face arriving at a
 * stop tangentially while sliding along it (normal rate ~0 and pressed into
 * it). The method's error is set
 * by its tolerance, c rtol with c < 0.01 measured on these scenes: runs at
 * rtol 1e-9 and 1e-10 on the output grids t_end / 8 and t_end / 64 must end
 * within 100 rtol L (L the scene's length; an angle counts as the
 * displacement of the farthest vertex) of the run at rtol 1e-11 on
 * t_end / 64, with no warnings. */
#include "../check.h"
#include "../sim_run.h"

#include <math.h>
#include <string.h>

/* zoo seed 7779 (tests/zoo.py: zoo_scene(7779).scene), t_end 0.16834853690105867 s,
 * length scale 0.002388683740519021 m, time scale 0.015604319106342997 s */
static exdex_scene_def zoo7779(void)
{
    exdex_scene_def d = exdex_default_scene_def();
    double inertia[9] = {1.2279797760603095e-11, 0.0, 0.0, 0.0, 7.119150398073803e-12, 0.0, 0.0, 0.0, 1.557143594430247e-11};
    double R0[9] = {1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0};
    double v[6][2] = {{0.000846348051352283, 0.0}, {0.0004231740256761416, 0.0010343304004481542}, {-0.00042317402567614135, 0.0010343304004481542}, {-0.000846348051352283, 1.462646948500973e-19}, {-0.0004231740256761419, -0.001034330400448154}, {0.0004231740256761416, -0.0010343304004481542}};
    d.mass = 2.1801023794094672e-05;
    memcpy(d.inertia, inertia, sizeof inertia);
    memcpy(d.R0, R0, sizeof R0);
    d.n_vertices = 6;
    memcpy(d.vertices, v, sizeof v);
    d.mu = 0.8195995552459763;
    d.grip_force = 0.0005576761086648412;
    d.e_r = 0.00031418103058186605;
    d.fingers = 2;
    d.patch_center[0] = -0.00016174295656144806;
    d.patch_center[1] = -0.000525607357647195;
    d.gravity[0] = 2.1232628048874553;
    d.gravity[1] = -0.21716414342400725;
    d.gravity[2] = -9.57500364470909;
    d.q0[0] = 0.0003332174762727948;
    d.q0[1] = 0.0006712969263235355;
    d.q0[2] = -0.05021647673454188;
    d.v0[0] = 0.0;
    d.v0[1] = 0.0;
    d.v0[2] = 0.0;
    d.p0[0] = -0.0014536750253009102;
    d.p0[1] = 0.003640393294095329;
    d.p0[2] = -0.0016977963827866545;
    d.slide_axis[0] = 0.8436988309324635;
    d.slide_axis[1] = 0.5368168055148744;
    d.dof = EXDEX_DOF_PLANAR;
    scene_eq7(&d, 0, -0.8699962575088404, 0.34356724875997197, 0.3536496253357485,
              -0.019985515295307628, 0.07149333827868333, 0.889590316622205);
    d.motion.center[0] = 0.0008535794753240262;
    d.motion.center[1] = 0.0017093463194573892;
    d.motion.center[2] = 0.0018261875306366214;
    scene_stop(&d, 0, 0.0016009684838738675, 0.0010202986277212161, -0.0015939749744541697,
               -0.6458424523598565, -0.4115959648827054, 0.6430212192626937);
    d.method = EXDEX_METHOD_EVENT;
    /* atol = rtol x 3.337265196175972e-06 (tests/zoo.py run) */
    return d;
}
/* zoo seed 4355 (tests/zoo.py: zoo_scene(4355).scene), t_end 1.7011862835268823 s,
 * length scale 0.4715486529775324 m, time scale 0.2192445218113667 s */
static exdex_scene_def zoo4355(void)
{
    exdex_scene_def d = exdex_default_scene_def();
    double inertia[9] = {0.9253680562840351, 0.0, 0.0, 0.0, 3.1160071011675927, 0.0, 0.0, 0.0, 2.86998848468647};
    double R0[9] = {1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0};
    d.mass = 136.55342796440289;
    memcpy(d.inertia, inertia, sizeof inertia);
    memcpy(d.R0, R0, sizeof R0);
    scene_rect(&d, 0.2357743264887662, 0.08638551702432554);
    d.mu = 0.9905847816357374;
    d.grip_force = 1421.5346827713736;
    d.e_r = 0.009743746478746398;
    d.fingers = 2;
    d.patch_center[0] = -0.005795024337678803;
    d.patch_center[1] = -0.006453814230539212;
    d.gravity[0] = -6.980439847420967;
    d.gravity[1] = 5.39338947803532;
    d.gravity[2] = 4.291958699097126;
    d.q0[0] = 0.12314255278658306;
    d.q0[1] = -0.07343222686737987;
    d.q0[2] = -0.6352312928954542;
    d.v0[0] = 0.0;
    d.v0[1] = 0.0;
    d.v0[2] = 0.0;
    d.p0[0] = -0.8687023935045785;
    d.p0[1] = -0.4490510784059249;
    d.p0[2] = -0.388385889541196;
    d.slide_axis[0] = 0.6831369449651306;
    d.slide_axis[1] = 0.7302902946251636;
    d.dof = EXDEX_DOF_PLANAR;
    scene_eq7(&d, 0, 0.33794438531981735, -0.9392537067998912, 0.05996721348766105,
              1.8414092099185742, 0.6609104840279355, 0.40855217303936364);
    d.motion.center[0] = -0.32867352054683985;
    d.motion.center[1] = -0.8722725358222307;
    d.motion.center[2] = 0.4510005232164628;
    scene_stop(&d, 0, -0.007575305579828588, -0.31743358875690625, -0.349006729004677,
               -0.016055028400514326, -0.6727656368529802, -0.7396814408465733);
    scene_stop(&d, 1, -0.5511977357971475, -0.1225530646310473, -0.1475145509132171,
               -0.9444650820582193, -0.209991955202526, -0.25276290772773885);
    d.method = EXDEX_METHOD_EVENT;
    /* atol = rtol x 0.4715486529775324 (tests/zoo.py run) */
    return d;
}
/* zoo seed 4421 (tests/zoo.py: zoo_scene(4421).scene), t_end 2.0091742850830165 s,
 * length scale 0.9447278892221066 m, time scale 0.31032650084650476 s */
static exdex_scene_def zoo4421(void)
{
    exdex_scene_def d = exdex_default_scene_def();
    double inertia[9] = {86.54287486640094, 0.0, 0.0, 0.0, 40.56216171522161, 0.0, 0.0, 0.0, 103.4772755561002};
    double R0[9] = {1.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 1.0, 0.0};
    d.mass = 1004.7474469131123;
    memcpy(d.inertia, inertia, sizeof inertia);
    memcpy(d.R0, R0, sizeof R0);
    scene_rect(&d, 0.2929800938875178, 0.4723639446110533);
    d.mu = 0.5335568432813993;
    d.grip_force = 47297.81470247877;
    d.e_r = 0.10612067185277305;
    d.fingers = 2;
    d.patch_center[0] = -0.00264411969806089;
    d.patch_center[1] = 0.15914019957063455;
    d.gravity[0] = 1.0272607446874176;
    d.gravity[1] = 0.024879324744377488;
    d.gravity[2] = -9.75603486984464;
    d.q0[0] = 0.02064158526652568;
    d.q0[1] = -0.1941635770844236;
    d.q0[2] = -1.7321187472003243;
    d.v0[0] = 0.0;
    d.v0[1] = 0.0;
    d.v0[2] = 0.0;
    d.p0[0] = -0.4874817681475995;
    d.p0[1] = -1.710513152235438;
    d.p0[2] = 0.4936634986649292;
    d.slide_axis[0] = 0.18507045041442047;
    d.slide_axis[1] = -0.9827252557980809;
    d.dof = EXDEX_DOF_PLANAR;
    scene_trapezoid(&d, 0, -0.6138142559350701, -0.7365685679145632, 0.28407534910858734,
                    2.0458767614715425, 1.3248216064172027, 2.881191577225251);
    d.motion.center[0] = -2.2855158572306014;
    d.motion.center[1] = -2.3237793180046555;
    d.motion.center[2] = 0.3071403120770595;
    scene_stop(&d, 0, -0.2754206723493871, 0.14677218139305687, 0.11606332638147321,
               0.8271625256198445, -0.4407964268484766, -0.34856945690610336);
    scene_stop(&d, 1, -1.4572027187095056, -0.9201497796414743, 0.8048192906764551,
               0.7661163418924151, 0.48376370296394483, -0.423129330559814);
    d.method = EXDEX_METHOD_EVENT;
    /* atol = rtol x 0.9447278892221066 (tests/zoo.py run) */
    return d;
}
/* zoo seed 5253 (tests/zoo.py: zoo_scene(5253).scene), t_end 0.7489275717477806 s,
 * length scale 0.012805452789366012 m, time scale 0.03612958440746683 s */
static exdex_scene_def zoo5253(void)
{
    exdex_scene_def d = exdex_default_scene_def();
    double inertia[9] = {6.899948839846372e-08, 0.0, 0.0, 0.0, 4.439308256348532e-08, 0.0, 0.0, 0.0, 5.706872241540932e-08};
    double R0[9] = {0.1643251060449712, 0.443461644092149, 0.8811010326531215, -0.30355495266042914, -0.8271608865052849, 0.4729262717920367, 0.9385369732933453, -0.34517624201975283, -0.0013083220121248296};
    d.mass = 0.002988485801427123;
    memcpy(d.inertia, inertia, sizeof inertia);
    memcpy(d.R0, R0, sizeof R0);
    scene_rect(&d, 0.004036544880026047, 0.006402726394683006);
    d.mu = 0.32725458663229434;
    d.grip_force = 0.015193008244969863;
    d.e_r = 0.0011574117427256556;
    d.fingers = 1;
    d.patch_center[0] = -0.0014482523467545681;
    d.patch_center[1] = -0.002554991538285729;
    d.gravity[0] = -1.525284358924961;
    d.gravity[1] = 0.7475502145849029;
    d.gravity[2] = -9.661820547965737;
    d.q0[0] = -0.0007093727580331791;
    d.q0[1] = -0.0007574027475938609;
    d.q0[2] = -0.5175706818760206;
    d.v0[0] = 0.0;
    d.v0[1] = 0.0;
    d.v0[2] = 0.0;
    d.p0[0] = -0.023849665790820106;
    d.p0[1] = -0.005810252508507204;
    d.p0[2] = 0.021925642122023626;
    d.slide_axis[0] = -0.27534337219030525;
    d.slide_axis[1] = -0.9613459457400707;
    d.dof = EXDEX_DOF_PLANAR;
    scene_eq7(&d, 1, 0.8811010326531215, 0.4729262717920367, -0.0013083220121248296,
              0.8872174691778334, 0.3480407647813984, 0.6165154588509041);
    d.motion.center[0] = -0.027098305514515045;
    d.motion.center[1] = 8.880611011342129e-05;
    d.motion.center[2] = 0.04459534783721356;
    scene_stop(&d, 0, 4.3424001758383325e-05, -0.0004760447571364174, 0.0001361001374573308,
               0.08736896482544512, -0.9578006622468797, 0.2738330794202345);
    d.method = EXDEX_METHOD_EVENT;
    /* atol = rtol x 0.0010592126776292703 (tests/zoo.py run) */
    return d;
}

static double qlast(const sim_run *r, int c) { return r->tr.q[(r->tr.n - 1) * 3 + c]; }

/* The check above for one scene: its t_end, length L, farthest vertex
 * radius and atol per unit rtol (tests/zoo.py run). */
static void grids_and_rtol_agree(exdex_scene_def d, double t_end, double L, double radius, double ascale)
{
    sim_run ref, r;
    d.rtol = 1e-11;
    d.atol = 1e-11 * ascale;
    ENSURE(sim_run_def(&d, t_end, t_end / 64, &ref) == EXDEX_OK);
    ENSURE(ref.st.warnings == 0);
    for (int k = 0; k < 4; k++) {
        double rtol = k < 2 ? 1e-9 : 1e-10, dist = 0.0;
        d.rtol = rtol;
        d.atol = rtol * ascale;
        ENSURE(sim_run_def(&d, t_end, t_end / (k % 2 ? 64 : 8), &r) == EXDEX_OK);
        for (int c = 0; c < 3; c++) dist = fmax(dist, fabs(qlast(&r, c) - qlast(&ref, c)) * (c == 2 ? radius : 1.0) / L);
        ENSURE(dist <= 100 * rtol);
        ENSURE(r.st.warnings == 0);
        sim_run_free(&r);
    }
    sim_run_free(&ref);
}

EXDEX_TEST(event_stops_separation_tie_4355)
{
    grids_and_rtol_agree(zoo4355(), 1.7011862835268823, 0.4715486529775324, 0.25110155432173525, 0.4715486529775324);
}

EXDEX_TEST(event_stops_corner_back_down_7779)
{
    grids_and_rtol_agree(zoo7779(), 0.16834853690105867, 0.002388683740519021, 0.0011175489400013722,
                         3.337265196175972e-06);
}

EXDEX_TEST(event_stops_corner_back_down_4421)
{
    grids_and_rtol_agree(zoo4421(), 2.0091742850830165, 0.9447278892221066, 0.5558462301597924, 0.9447278892221066);
}

EXDEX_TEST(event_stops_face_arrives_tangentially_5253)
{
    grids_and_rtol_agree(zoo5253(), 0.7489275717477806, 0.012805452789366012, 0.007568923295531204,
                         0.0010592126776292703);
}
