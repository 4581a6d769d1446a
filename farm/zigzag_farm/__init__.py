"""zigzag-farm: zigzag renders as Dask jobs (frames, cameras, image regions)."""
