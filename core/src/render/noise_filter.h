/*
 * noise_filter.h — the FILTERING stage: the user's noise filter
 * (filters/image_filter.h) run over the rendered film, on the part of the
 * image the filter target names (enum phos_filter_target), the rest
 * added back unfiltered.
 */
#ifndef PHOS_NOISE_FILTER_H
#define PHOS_NOISE_FILTER_H

#include "render/render.h"

/* Filters the film's Combined pass in place (its unfiltered copy goes to
 * the Noisy Image pass if that is on) and hands every tile to the host
 * again. PHOS_ERROR_CANCELLED on a cancel, PHOS_ERROR_OUT_OF_MEMORY. */
phos_status render_filter(render *r);

#endif /* PHOS_NOISE_FILTER_H */
