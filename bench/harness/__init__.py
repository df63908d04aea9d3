"""The benchmark harness's library: experiments as data, results, metrics, and the routes to render."""
