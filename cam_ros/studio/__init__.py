"""cam_ros studio: a design file edited in the browser, every check from the core as it changes.

A shell like the command line: the page (static/) draws what the app (app.py) answers; the
app turns the page's values into the core's (document.py), asks the core for what to draw
(view.py) and has the CLI's own commands make the report and the downloads (exports.py);
with --node it shows and drives a running cam_node (live.py).
Nothing here is computed that the core or the CLI computes.
"""
