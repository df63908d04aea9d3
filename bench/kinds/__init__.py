"""What an experiment can be: each module here runs one kind of experiment (`run(experiment, results)`)."""
