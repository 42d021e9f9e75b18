"""The syntheses of the sources' machines: each turns its design inputs into a mechanism file (a
:class:`~mechatron.model.linkage.LinkageSpec`) — the six-link bucket's c and L2 [Bucket], the front shovel's working
device [Shovel], the seven-link reconstruction [ShiLiang], the grab [Mikhailov] — and holds what is particular to that
machine (working range, tool forces, scooping loads; the front shovel's rated lift capacity [ISO 10567], rated tool
forces [ISO 6015] and digging capability on the rest of its machine). The shipped machines themselves are files in
``robots/``, loaded by name with :func:`mechatron.load` like any user's file.
"""
