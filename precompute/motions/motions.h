/* precompute/motions: training motions for the data-driven methods (romkit motions).
 *
 * The Grassmann paper trains its decoders on "long-duration dynamic simulations in which each
 * object is repeatedly dropped into a Pachinko-style environment and tumbled in a dryer-like
 * setting" (adaptive-linear-rom-grassmann, Sec. 6). This stage writes such scenes around a scene's
 * one object, for romkit fom to run and for the methods that train on other runs (rom.training:
 * a pod basis, a CROM or quadratic_pod decoder, a cubature) to list:
 *
 *   pachinko  a board of staggered rows of pegs (capsules across the board) below the object,
 *             side walls, a front and a back wall and a floor (planes); each scene drops the object
 *             from its own place along the board with its own initial velocity.
 *   dryer     a closed drum (an octagonal prism, a triangle-mesh obstacle written beside the
 *             scenes) around the object, turning about its axis (a twist); each scene starts the
 *             object with its own velocity and turns the drum at its own rate and sense.
 *
 * Sizes are in units of the object's largest extent L (measured on the built scene, along the
 * directions gravity sets), so any object fits: pegs of radius 0.1 L, 2.4 L apart (a gap of 2.2 L
 * it can pass), rows 1.6 L apart; the drum's inner radius is the object's half diagonal plus
 * 0.25 L, so it can turn over in it, and it turns at 0.3-0.7 of the rate at which the object would
 * be pressed to the wall (sqrt(g / radius)), so it is carried up and falls back (tumbles).
 * Every obstacle starts at least 0.25 L clear of the object's bounding box. */
#ifndef RK_MOTIONS_H
#define RK_MOTIONS_H

#include <stdint.h>

#include "util/util.h"

typedef enum { RK_MOTIONS_PACHINKO, RK_MOTIONS_DRYER } rk_motions_kind;

typedef struct {
    rk_motions_kind kind;
    int count;          /* scenes to write, 1..RK_MOTIONS_MAX */
    uint64_t seed;      /* the draws' seed (rk_splitmix64): the same seed writes the same files */
    double duration;    /* s; 0: the template's time.duration */
    double speed;       /* m/s: the largest initial speed drawn; 0: RK_MOTIONS_SPEED */
} rk_motions_options;

#define RK_MOTIONS_MAX 1000
#define RK_MOTIONS_SPEED 1.0

/* What was drawn for one scene. */
typedef struct {
    double offset;       /* m: the object's shift along the board (pachinko; 0 in the dryer) */
    double velocity[3];  /* m/s */
    double spin;         /* deg/s: the drum's rate, signed (dryer; 0 on the board) */
} rk_motions_draw;

typedef struct {
    double extent;        /* L (m) */
    int obstacles;        /* per scene */
    int pegs;             /* pachinko */
    double drum_radius;   /* dryer: the octagon's inner radius (m) */
    int replaced;         /* the template's own obstacles, dropped */
    rk_motions_draw draw[RK_MOTIONS_MAX];
} rk_motions_report;

/* The scene file names written for o: DIR/<kind>_<k>.json, k = 0..count-1 (the dryer's drum:
 * DIR/drum.obj). Writes them from the scene at template_path, which must hold one object with
 * nothing fixed or moving, and gravity. The scenes keep the template's object (mesh, material,
 * regions, loads), time, contact, damping and newton sections; its rom and reference sections and
 * obstacles go (a training run is full order), its mesh file becomes an absolute path, and contact
 * without a given friction gets 0.3 (a drum carries the object up by friction). DIR is made if
 * absent. Nothing is written when it fails: each file is atomic, and the ones already written are
 * removed (and DIR, if made here). */
int rk_motions_write(const char *template_path, const rk_motions_options *o, const char *dir, rk_motions_report *rep,
                     rk_error *err);
/* "pachinko" / "dryer" */
const char *rk_motions_kind_name(rk_motions_kind k);

#endif
