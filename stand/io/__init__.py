"""Files in and out: atomic writes (:mod:`.atomic`), JSON (:mod:`.jsonable`)."""
