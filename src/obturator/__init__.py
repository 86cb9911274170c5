"""obturator: ball obturator opening dynamics (Bloomer 1980)."""
