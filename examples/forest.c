/* forest.c - the bake methods side by side on the generated forest (tools/gen.h: trees of a trunk
   and leaf clusters, clearings, a path), one cell's PVS from above per method: OUTDIR/forest.png
   (default build/demo). A forest is the hard case of the papers: no single tree hides much, and
   only fusing the many small occluders (Durand 2000's occlusion sweep, Wonka 2000's cull-map
   fusion) could cull; the panels show what each method manages, the ray-sampled reference, and
   AUTO with a 30 m draw distance (pvsbake --max-distance).
   Usage: pvsforest [-o OUTDIR] */
#include "methods_view.h"

int main(int argc, char **argv) {
    methods_view_opts o;
    memset(&o, 0, sizeof(o));
    o.kind = GEN_FOREST;
    o.size = 0.35f;
    o.seed = 1;
    o.radius = 45.0f;
    o.title = "forest";
    o.png_name = "forest.png";
    o.max_distance = 30.0f; /* what engines do in forests: a draw distance, here baked into the PVS */
    return methods_view_main(&o, argc, argv);
}
