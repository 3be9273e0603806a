/* The two-object incline of test_pipeline_friction_objects (the reduced simulator and full order)
 * and test_runtime_object_contact (the runtime): a 2 m slab of one cell, held, and on it a
 * 10 x 5 x 10 cm block of stiff rubber at dhat / 2 above its top; gravity g tilted by atan(tan_theta)
 * makes the incline. One scene text, so both tests judge the same setup. */
#ifndef RK_TEST_INCLINE_SLAB_H
#define RK_TEST_INCLINE_SLAB_H

#include <math.h>
#include <stdio.h>

static void incline_slab_scene(char *json, size_t cap, double g, double mu, double tan_theta, double eps_v)
{
    double theta = atan(tan_theta);
    snprintf(json, cap,
             "{\"objects\": [{\"mesh\": {\"box\": {\"size\": [2.0, 0.05, 0.3], \"cells\": [1, 1, 1]}},"
             "   \"material\": {\"model\": \"neohookean\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000},"
             "   \"fixed\": [{\"box\": [[-1, -1, -1], [3, 1, 1]]}]},"
             "  {\"mesh\": {\"box\": {\"size\": [0.1, 0.05, 0.1], \"cells\": [2, 1, 2]}, \"translate\": [0.1, 0.0505, 0.1]},"
             "   \"material\": {\"model\": \"neohookean\", \"young\": 1e6, \"poisson\": 0.3, \"density\": 1000}}],"
             " \"gravity\": [%.17g, %.17g, 0],"
             " \"contact\": {\"dhat\": 1e-3, \"friction\": %.17g, \"eps_v\": %.17g},"
             " \"time\": {\"step\": 0.01, \"duration\": 1.0}, \"rom\": {\"basis\": \"modes\", \"size\": 12}}",
             g * sin(theta), -g * cos(theta), mu, eps_v);
}

#endif
