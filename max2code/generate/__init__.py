"""Generating code: the .mxm grammar and reader, the Maxima driver, the
expression reader, collection by powers of t, lowering, variants, exact
motion and the pipeline that chains them."""
