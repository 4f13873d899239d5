"""``lanterna fit``: PTM, HSH, photometric-stereo and Ward models fitted from multi-light
photographs in one streamed pass, locally or on a Dask cluster, with a leave-one-out report."""
