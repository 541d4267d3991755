"""Stage 5, classification: a model and a scene in, answers out.

In: a model folder (``rules.pl``) and a cloud or a data set.  Out: a class per object with the
rule and the planes that prove it (:mod:`.classifier`), and the explanation images
(:mod:`.explain_render`).  The classifier's names are re-exported here
(``from planerel.classify import Classifier``).
"""

from planerel.classify.classifier import *  # noqa: F401,F403
from planerel.classify.classifier import __all__  # noqa: F401
