// Runs a Flamenco job type's compileJob(job) outside Flamenco, with stand-ins for what the Manager
// provides (author, path, print), and prints the tasks it made as JSON:
//   node flamenco_compile.js JOB_TYPE.js '{"passes": 8, ...}'
// Flamenco's `path` module is POSIX path handling, as Node's path.posix.
const fs = require("fs");
const vm = require("vm");

const [jobTypeFile, settingsJson] = process.argv.slice(2);
const tasks = [];
const context = {
    path: require("path").posix,
    print: () => {},
    author: {
        Task: (name, type) => ({
            name, type, commands: [], dependencies: [],
            addCommand(command) { this.commands.push(command); },
            addDependency(task) { this.dependencies.push(task.name); },
        }),
        Command: (type, parameters) => ({ type, parameters }),
    },
};
vm.createContext(context);
vm.runInContext(fs.readFileSync(jobTypeFile, "utf8") + "\nthis.JOB_TYPE = JOB_TYPE; this.compileJob = compileJob;", context);
const job = { settings: JSON.parse(settingsJson), addTask: (task) => tasks.push(task) };
context.compileJob(job);
console.log(JSON.stringify({
    label: context.JOB_TYPE.label,
    tasks: tasks.map((t) => ({ name: t.name, type: t.type, commands: t.commands, dependencies: t.dependencies })),
}));
