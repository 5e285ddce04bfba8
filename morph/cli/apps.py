"""Applications of sums: offsets and C-space obstacles."""

import click
import numpy as np

from .group import main
from .options import (InputError, common_options, report_written, resolve_output,
                      shape_argument, write_image, writer_budget)


@main.command()
@shape_argument("shape")
@click.option("--radius", "-r", type=float, required=True,
              help="Offset radius: in em for glyphs (0.05 = 50 units at 1000 units "
                   "per em), in user units for SVG. Negative: an inset (the shape "
                   "shrunk by the disk).")
@common_options
def offset(shape, radius, font, tol, output, force, size):
    """Offset a shape by an exact disk: SHAPE ⊕ disk(RADIUS) (Fig. 37), or for a
    negative RADIUS the inset SHAPE ⊖ disk(-RADIUS).

    The disk is an exact rational circle, so the boundary is the QAC convolution
    with a circle trimmed to the boundary, within --tol of the exact offset curve.
    Outward, holes shrink and close; inward, holes grow and parts narrower than
    twice the radius vanish (a shape that vanishes entirely: exit 2).  The
    picture shows the larger region in blue with the smaller on top in black.

    \b
    Examples:
      morph offset o --radius 0.04 -o o-offset.png
      morph offset drawing.svg --radius 5 -o grown.svg
      morph offset o --radius -0.02 -o o-inset.svg
    """
    from ..offset import offset_region
    from ..piece import circle as pc_circle

    if not np.isfinite(radius):
        raise InputError("--radius must be a finite number, got %s" % radius)
    out = resolve_output(output, "%s-%s.png" % ("inset" if radius < 0 else "offset",
                                               shape.slug), force)
    r = shape.em_to_units(radius)
    budget = writer_budget(shape, tol, *([[pc_circle((0.0, 0.0), abs(r))]] if r else []))
    loops = offset_region(shape.region, r, budget.geometry)
    if not loops:
        raise InputError("--radius %g erodes all of %s '%s': no disk of radius %g%s fits in it"
                         % (radius, shape.kind, shape.name, -radius,
                            " em" if shape.kind == "glyph" else ""))
    big, small = (loops, shape.region) if r >= 0 else (shape.region, loops)
    # the export gets what the offset left of --tol (its achieved bound <= its share)
    write_image(out, [(big, {"fill": "#9bbbd4"}), (small, {"fill": "black"})],
                size=size, tol=budget.after(loops.bound))
    report_written(out, loops)


@main.command()
@shape_argument("obstacle")
@shape_argument("robot")
@click.option("--samples", type=click.IntRange(min=0, max=200), default=8,
              show_default=True, help="Robot copies drawn along the C-space boundary.")
@click.option("--reference", type=click.Choice(["centroid", "origin"]), default="centroid",
              show_default=True,
              help="The robot's reference point: its area centroid or its origin.")
@click.option("--inside", is_flag=True,
              help="OBSTACLE is a container the robot must stay in: the region drawn is "
                   "where the robot fits, OBSTACLE ⊖ (ROBOT − ref).")
@common_options
def cspace(obstacle, robot, samples, reference, inside, font, tol, output, force, size):
    """C-space obstacle of a translating ROBOT: OBSTACLE ⊕ (−ROBOT) (Figs. 4, 38).

    The robot's reference point is its area centroid (--reference centroid) or
    its origin (glyph origin, SVG user-space origin after the y flip).  The robot,
    with its reference point at p, overlaps
    the obstacle exactly when p lies in the C-space region.  The picture shows the
    C-space region (orange), the obstacle (dark grey) and the robot outline placed
    at SAMPLES points along the C-space boundary (touching the obstacle).  With
    --inside the robot moves inside OBSTACLE (a room): the region is where it fits,
    drawn over the room, with the robot placed touching the walls from inside; a
    robot that fits nowhere is an error (exit 2).

    \b
    Examples:
      morph cspace O v -o cspace.png
      morph cspace room.svg robot.svg --samples 12
      morph cspace room.svg robot.svg --inside
    """
    from ..cspace import cspace_obstacle, free_space
    from ..region import region_centroid
    from ..render import cspace_figure

    out = resolve_output(output, "cspace-%s-%s.png" % (obstacle.slug, robot.slug), force)
    budget = writer_budget(obstacle, tol, robot.region)
    ref = region_centroid(robot.region) if reference == "centroid" else (0.0, 0.0)
    space = free_space if inside else cspace_obstacle
    loops = space(obstacle.region, robot.region, budget.geometry, reference=ref)
    if not loops:
        raise InputError("%s '%s' fits nowhere inside %s '%s'" % (robot.kind, robot.name,
                                                                 obstacle.kind, obstacle.name))
    # the SVG export gets the rest of --tol beyond the error the sum achieved
    write_image(out, cspace_figure(obstacle.region, robot.region, loops, budget.total, samples, ref,
                                   inside=inside),
                size=size, tol=budget.after(loops.bound))
    report_written(out, loops)
