"""The browser studio: a FastAPI app (:mod:`.app`) binding one project's model to its
pages over one websocket. :mod:`.protocol` declares every message, both directions;
:mod:`.handlers` maps a page's message to the :mod:`.session`, which binds the
:mod:`.editor` (scene, history, commands), the take recorder (:mod:`.takes`) and the
project file; :mod:`.outbound` builds what the pages see, :mod:`.defaults` the scene a
new project starts with. The page itself is in ``web/``."""
