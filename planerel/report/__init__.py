"""The report: a data set and options in, an HTML page with figures out.

In: a data set (synthetic or real) and :class:`ReportOptions`.  Out: ``report.html``, its figures
and tables (:mod:`.builder`, re-exported here; :mod:`.sections`, :mod:`.figures`,
:mod:`.render`, and :mod:`.browser` for the headless-browser check).
"""

from planerel.report.builder import *  # noqa: F401,F403
from planerel.report.builder import __all__  # noqa: F401
