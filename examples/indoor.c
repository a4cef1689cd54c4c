/* indoor.c - the bake methods side by side on the generated office floor (tools/gen.h: rooms on
   both sides of corridors, doors, a column hall, furniture), one cell's PVS from above per method:
   OUTDIR/indoor.png (default build/demo). Walls are thick boxes standing on the floor, so the 2.5D
   method (otree) applies as well as the 3D ones; ceilings and lintels are left out of the picture.
   Usage: pvsindoor [-o OUTDIR] */
#include "methods_view.h"

int main(int argc, char **argv) {
    methods_view_opts o;
    memset(&o, 0, sizeof(o));
    o.kind = GEN_INDOOR;
    o.size = 1.0f;
    o.seed = 1;
    o.radius = 0.0f;
    o.title = "indoor";
    o.png_name = "indoor.png";
    return methods_view_main(&o, argc, argv);
}
