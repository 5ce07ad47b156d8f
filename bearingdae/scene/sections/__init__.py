"""One module per group of scene-file sections: the pydantic models of the file as written
(types, ranges, unknown keys). :mod:`bearingdae.scene.schema` assembles them into the scene."""
