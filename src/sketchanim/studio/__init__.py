"""The browser studio: a FastAPI app (:mod:`.app`) binding one project's model
(:mod:`.session`) to its pages over one websocket (:mod:`.protocol`, :mod:`.commands`);
the page itself is in ``web/``."""
