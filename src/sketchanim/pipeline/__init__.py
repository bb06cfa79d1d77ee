"""One library function per input kind: a sample table (:func:`reduce_table`, with
:class:`TableOptions`) and a clip (:func:`reduce_clip_file`, with :class:`ClipOptions`);
a folder of clips is :func:`sketchanim.batch.reduce_folder`. Each options object is
frozen and checked once against :data:`sketchanim.limits.LIMITS`; errors name fields."""

from sketchanim.pipeline.clip import ClipOutcome, ClipReduction, reduce_clip_file
from sketchanim.pipeline.clip_options import ClipOptions
from sketchanim.pipeline.table import TableReduction, reduce_table
from sketchanim.pipeline.table_options import TableOptions
from sketchanim.pipeline.table_outputs import Written

__all__ = ["ClipOptions", "ClipOutcome", "ClipReduction", "TableOptions", "TableReduction", "Written",
           "reduce_clip_file", "reduce_table"]
