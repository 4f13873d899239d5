-- wrk script: GET the request paths listed in the file $LOAD_URLS (one a line), cycling.
--
-- Each wrk thread starts at a different offset of the list. With $LOAD_MAX_PER_THREAD > 0 a
-- thread stops after that many responses (a bound on the request count besides wrk's -d);
-- the response hook costs client CPU, so it is only installed then. done() prints one line of
-- JSON: requests, duration, bytes, socket/status errors and latency percentiles (microseconds).

local paths = {}
for line in io.lines(os.getenv("LOAD_URLS")) do
  if #line > 0 then paths[#paths + 1] = line end
end
local limit = tonumber(os.getenv("LOAD_MAX_PER_THREAD") or "0")
local threads = 0
local counter = 0
local responses = 0

function setup(thread)
  thread:set("thread_index", threads)
  threads = threads + 1
end

function init(args)
  counter = (thread_index or 0) * 7919
end

function request()
  counter = counter + 1
  return wrk.format("GET", paths[(counter % #paths) + 1])
end

if limit > 0 then
  function response(status, headers, body)
    responses = responses + 1
    if responses >= limit then wrk.thread:stop() end
  end
end

function done(summary, latency, requests)
  local e = summary.errors
  io.write(string.format(
    '{"paths": %d, "requests": %d, "duration_us": %d, "bytes": %d, ' ..
    '"errors": {"connect": %d, "read": %d, "write": %d, "status": %d, "timeout": %d}, ' ..
    '"latency_us": {"p50": %d, "p90": %d, "p99": %d, "max": %d, "mean": %.1f}}\n',
    #paths, summary.requests, summary.duration, summary.bytes,
    e.connect, e.read, e.write, e.status, e.timeout,
    latency:percentile(50), latency:percentile(90), latency:percentile(99),
    latency.max, latency.mean))
end
