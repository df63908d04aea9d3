"""One still across many machines: its passes rendered as shares and merged (engine/ppm/share.h).

- scene_record.py: an exported core scene as plain data (the builder calls), replayed on a worker;
- still_export.py: a .blend's still exported once with the add-on's settings (needs bpy);
- shares.py: what a worker runs (needs only ppm_core and numpy) and the plan of pass ranges;
- exr.py: the merged image written with its error estimate;
- __main__.py: `python -m ppm_render.farm scene.blend --scheduler tcp://host:8786 --shares 64
  --output out.exr` on dask.distributed (docs/FARM.md).
"""
