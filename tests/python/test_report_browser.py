"""The offline HTML report in a real browser: Debian's chromium driven by Selenium through chromedriver.

For a run with a threat (`es-e0`) and one with obstacles (`pigeon-baseline`, shortened, with its
trajectory on), the page opened from file:// logs no error, its displayed time moves when Play is clicked
and when the slider moves, and a screenshot is saved (its path is printed).

Without chromium and chromedriver (/usr/bin/chromium and /usr/bin/chromedriver, or $SATFLOCK_CHROMIUM and
$SATFLOCK_CHROMEDRIVER) the test is skipped, unless SATFLOCK_REQUIRE_BROWSER or CI is set (`.ci/run`
installs them and sets SATFLOCK_REQUIRE_BROWSER=1): then it fails. Screenshots are copied to
$SATFLOCK_SCREENSHOT_DIR (default: the system temporary folder) and their paths printed.
"""

import os
import pathlib
import re
import shutil
import tempfile
import time

import pytest

from conftest import ROOT, run_satflock

CHROMIUM = pathlib.Path(os.environ.get("SATFLOCK_CHROMIUM", "/usr/bin/chromium"))
CHROMEDRIVER = pathlib.Path(os.environ.get("SATFLOCK_CHROMEDRIVER", "/usr/bin/chromedriver"))


def browser_missing_reason():
    missing = [str(p) for p in (CHROMIUM, CHROMEDRIVER) if not p.exists()]
    if missing:
        return (f"no {' and no '.join(missing)}: install Debian's chromium and chromium-driver "
                "(apt-get install chromium chromium-driver) to run the report's browser test")
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (pip install -r tests/python/requirements.txt)"
    return None


@pytest.fixture
def browser(tmp_path):
    reason = browser_missing_reason()
    if reason:
        if os.environ.get("SATFLOCK_REQUIRE_BROWSER") or os.environ.get("CI"):
            pytest.fail(f"the browser test is required here (CI / SATFLOCK_REQUIRE_BROWSER): {reason}")
        pytest.skip(reason)
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = str(CHROMIUM)
    for flag in ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--window-size=1280,2000", f"--user-data-dir={tmp_path / 'chromium-profile'}"):
        options.add_argument(flag)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(str(CHROMEDRIVER)), options=options)
    # Every uncaught error and rejected promise, from before the page's own script runs.
    driver.execute_cdp_cmd("Page.addScriptToEvaluateOnNewDocument", {"source": """
        window.__satflockErrors = [];
        window.addEventListener('error', e => window.__satflockErrors.push(String(e.message)));
        window.addEventListener('unhandledrejection', e => window.__satflockErrors.push(String(e.reason)));
    """})
    yield driver
    driver.quit()


def shortened_pigeon(directory: pathlib.Path) -> pathlib.Path:
    """pigeon-baseline (two obstacles) for 60 s with its trajectory written."""
    text = (ROOT / "scenarios" / "pigeon-baseline.toml").read_text()
    text, n_duration = re.subn(r"(?m)^duration_s = .*$", "duration_s = 60.0", text)
    text, n_trajectory = re.subn(r"(?m)^trajectory = false.*$", "trajectory = true", text)
    assert n_duration == 1 and n_trajectory == 1, "pigeon-baseline.toml changed shape"
    path = directory / "pigeon-short.toml"
    path.write_text(text)
    return path


def displayed_time(driver) -> str:
    return driver.find_element("id", "time-display").text


def check_page(driver, report: pathlib.Path, shot: pathlib.Path, n_threats: int, n_obstacles: int):
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.actions.wheel_input import ScrollOrigin
    from selenium.webdriver.common.keys import Keys

    driver.get(report.as_uri())
    assert driver.execute_script("return document.readyState") == "complete"
    kept = driver.find_element("id", "viewer-kept")
    assert int(kept.get_attribute("data-times")) > 10
    scene = driver.execute_script(
        "return JSON.parse(document.getElementById('satflock-data').textContent).scene")
    assert (len(scene["threats"]), len(scene["obstacles"])) == (n_threats, n_obstacles)
    # The view drew something: canvas pixels that are not the background.
    painted = driver.execute_script("""
        const c = document.getElementById('view');
        const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
        let n = 0;
        for (let i = 3; i < d.length; i += 4) if (d[i] > 0) n++;
        return n;""")
    assert painted > 100

    before = displayed_time(driver)
    assert before.startswith("t = 0 s"), before
    assert "UTC" in before
    driver.find_element("id", "play").click()
    time.sleep(1.5)
    playing = displayed_time(driver)
    assert playing != before, "Play did not move the displayed time"
    driver.find_element("id", "play").click()  # pause
    paused = displayed_time(driver)
    time.sleep(0.5)
    assert displayed_time(driver) == paused, "Pause did not stop the time"

    slider = driver.find_element("id", "time-slider")
    slider.send_keys(Keys.END)
    end = displayed_time(driver)
    assert end != paused, "moving the slider did not change the displayed time"
    assert slider.get_attribute("value") == slider.get_attribute("max")
    slider.send_keys(Keys.HOME)
    for _ in range(5):
        slider.send_keys(Keys.ARROW_RIGHT)
    assert slider.get_attribute("value") == "5"
    assert "time 6 of" in displayed_time(driver)

    # Colour by the law's output column, and a drag (rotation) and a wheel (zoom) on the canvas.
    options = [o.get_attribute("value") for o in driver.find_elements("css selector", "#colour-by option")]
    assert len(options) >= 2, options
    canvas = driver.find_element("id", "view")
    ActionChains(driver).click_and_hold(canvas).move_by_offset(60, 25).release().perform()
    ActionChains(driver).scroll_from_origin(ScrollOrigin.from_element(canvas), 0, -200).perform()

    driver.find_element("id", "reset-view").click()
    driver.execute_script("document.getElementById('viewer').scrollIntoView()")
    assert driver.save_screenshot(str(shot))
    severe = [e for e in driver.get_log("browser") if e["level"] == "SEVERE"]
    assert severe == [], severe
    errors = driver.execute_script("return window.__satflockErrors")
    assert errors == [], errors


def keep_screenshot(shot: pathlib.Path) -> pathlib.Path:
    """A copy of a screenshot where it outlives pytest's tmp dir; its path is printed."""
    directory = pathlib.Path(os.environ.get("SATFLOCK_SCREENSHOT_DIR", tempfile.gettempdir()))
    directory.mkdir(parents=True, exist_ok=True)
    kept = directory / f"satflock-report-{shot.name}"
    shutil.copyfile(shot, kept)
    print(f"report screenshot: {kept}")
    return kept


def test_report_with_a_threat_plays_in_a_browser(satflock_bin, browser, tmp_path):
    out = tmp_path / "es"
    run_satflock(satflock_bin, "run", "es-e0", "--out", str(out), "--quiet", "--report")
    shot = tmp_path / "es-e0.png"
    check_page(browser, out / "report.html", shot, n_threats=1, n_obstacles=0)
    keep_screenshot(shot)


def test_report_with_obstacles_plays_in_a_browser(satflock_bin, browser, tmp_path):
    out = tmp_path / "pigeon"
    run_satflock(satflock_bin, "run", str(shortened_pigeon(tmp_path)), "--out", str(out), "--quiet")
    run_satflock(satflock_bin, "report", str(out))
    shot = tmp_path / "pigeon.png"
    check_page(browser, out / "report.html", shot, n_threats=0, n_obstacles=2)
    keep_screenshot(shot)
